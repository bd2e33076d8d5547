// PNG charts drawn with OpenCV and CSV output; see chart.h.
#include "host/util/chart.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "host/util/image_io.h"

namespace lorgnette {

void write_chart(const std::string& path, const ChartSpec& spec, const std::vector<ChartSeries>& series) {
  cv::Mat img(spec.height, spec.width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 80, right = 190, top = 40, bottom = 60;
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  auto tx = [&](double x) { return spec.log_x ? std::log10(std::max(x, 1e-12)) : x; };
  for (const auto& s : series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, tx(s.x[i])), x1 = std::max(x1, tx(s.x[i]));
      y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
    }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 - x0 < 1e-12) x0 -= 0.5, x1 += 0.5;
  if (y1 - y0 < 1e-12) y0 -= 0.5, y1 += 0.5;
  double pad = 0.05 * (y1 - y0);
  y0 -= pad, y1 += pad;
  const int pw = spec.width - left - right, ph = spec.height - top - bottom;
  auto px = [&](double x) { return left + static_cast<int>((tx(x) - x0) / (x1 - x0) * pw); };
  auto py = [&](double y) { return top + ph - static_cast<int>((y - y0) / (y1 - y0) * ph); };
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  cv::rectangle(img, {left, top}, {left + pw, top + ph}, cv::Scalar(0, 0, 0), 1);
  for (int i = 0; i <= 5; ++i) {
    double fx = x0 + (x1 - x0) * i / 5, fy = y0 + (y1 - y0) * i / 5;
    int gx = left + pw * i / 5, gy = top + ph - ph * i / 5;
    cv::line(img, {gx, top}, {gx, top + ph}, cv::Scalar(225, 225, 225), 1);
    cv::line(img, {left, gy}, {left + pw, gy}, cv::Scalar(225, 225, 225), 1);
    std::string xl = spec.log_x ? fmt::format("{:.3g}", std::pow(10.0, fx)) : fmt::format("{:.3g}", fx);
    cv::putText(img, xl, {gx - 15, top + ph + 18}, font, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(img, fmt::format("{:.3g}", fy), {8, gy + 4}, font, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  cv::putText(img, spec.title, {left, 25}, font, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, spec.x_label, {left + pw / 2 - 60, spec.height - 15}, font, 0.5, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::putText(img, spec.y_label, {8, top - 8}, font, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  static const cv::Scalar palette[] = {{200, 80, 30},  {40, 40, 220},   {40, 160, 40}, {160, 40, 160},
                                       {30, 160, 200}, {100, 100, 100}, {0, 120, 255}, {120, 60, 0}};
  for (size_t si = 0; si < series.size(); ++si) {
    const auto& s = series[si];
    cv::Scalar col = palette[si % 8];
    std::vector<cv::Point> pts;
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) pts.emplace_back(px(s.x[i]), py(s.y[i]));
    if (!s.points_only && pts.size() > 1) cv::polylines(img, pts, false, col, 2, cv::LINE_AA);
    for (const auto& p : pts) cv::circle(img, p, 3, col, cv::FILLED, cv::LINE_AA);
    int ly = top + 15 + 20 * static_cast<int>(si);
    cv::line(img, {left + pw + 10, ly - 4}, {left + pw + 30, ly - 4}, col, 2);
    cv::putText(img, s.name, {left + pw + 35, ly}, font, 0.42, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  std::vector<uchar> png;
  if (!cv::imencode(".png", img, png)) throw std::runtime_error("cannot encode chart " + path);
  write_text_file_atomic(path, std::string(png.begin(), png.end()));
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream out;
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  for (const auto& r : rows) {
    for (size_t i = 0; i < r.size(); ++i) out << (i ? "," : "") << r[i];
    out << "\n";
  }
  write_text_file_atomic(path, out.str());
}

}  // namespace lorgnette
