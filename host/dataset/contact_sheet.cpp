// Contact sheets: a grid of area-averaged thumbnails with a text label under each (OpenCV's Hershey
// font drawn directly into the linear float image). Layout rules are in media.h.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host/dataset/media.h"
#include "host/dataset/metrics.h"

namespace lorgnette::dataset {
namespace {

// Draws `text` centred in the strip, shrinking the font until it fits the width.
void draw_label(cv::Mat& sheet, const std::string& text, cv::Rect strip, const std::array<float, 3>& colour) {
  if (text.empty() || strip.height < 6) return;
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  double scale = strip.height / 30.0 + 0.1;
  int base = 0;
  cv::Size sz = cv::getTextSize(text, font, scale, 1, &base);
  while (sz.width > strip.width - 2 && scale > 0.2) {
    scale *= 0.9;
    sz = cv::getTextSize(text, font, scale, 1, &base);
  }
  cv::Point org(strip.x + std::max(0, (strip.width - sz.width) / 2),
                strip.y + (strip.height + sz.height) / 2);
  cv::putText(sheet, text, org, font, scale, cv::Scalar(colour[0], colour[1], colour[2]), 1, cv::LINE_AA);
}

}  // namespace

Image make_contact_sheet(const std::vector<Image>& images, const std::vector<std::string>& labels,
                         const ContactSheetOptions& o) {
  if (images.empty()) throw std::runtime_error("contact sheet: no images");
  if (!labels.empty() && labels.size() != images.size())
    throw std::runtime_error(
        fmt::format("contact sheet: {} labels for {} images", labels.size(), images.size()));
  if (o.cell_width < 1 || o.padding < 0 || o.label_height < 0)
    throw std::runtime_error("contact sheet: cell_width must be >= 1, padding and label_height >= 0");
  int n = static_cast<int>(images.size());
  int cols = o.columns > 0 ? std::min(o.columns, n) : static_cast<int>(std::ceil(std::sqrt(n)));
  int rows = (n + cols - 1) / cols;
  int cell_h = std::max(1, static_cast<int>(std::lround(o.cell_width * static_cast<double>(images[0].height) /
                                                        std::max(1, images[0].width))));
  int label_h = labels.empty() ? 0 : o.label_height;
  Image sheet(cols * o.cell_width + (cols + 1) * o.padding,
              rows * (cell_h + label_h) + (rows + 1) * o.padding, 3);
  cv::Mat mat(sheet.height, sheet.width, CV_32FC3, sheet.pixels.data());
  mat.setTo(cv::Scalar(o.background[0], o.background[1], o.background[2]));
  for (int i = 0; i < n; ++i) {
    const Image& img = images[i];
    if (img.empty() || img.channels < 3)
      throw std::runtime_error(fmt::format("contact sheet: image {} is empty or not RGB(A)", i));
    int x0 = o.padding + (i % cols) * (o.cell_width + o.padding);
    int y0 = o.padding + (i / cols) * (cell_h + label_h + o.padding);
    double s =
        std::min(static_cast<double>(o.cell_width) / img.width, static_cast<double>(cell_h) / img.height);
    int tw = std::clamp(static_cast<int>(std::lround(img.width * s)), 1, o.cell_width);
    int th = std::clamp(static_cast<int>(std::lround(img.height * s)), 1, cell_h);
    Image rgb = composite_over(img, o.background);
    cv::Mat src(rgb.height, rgb.width, CV_32FC3, rgb.pixels.data());
    cv::Mat roi = mat(cv::Rect(x0 + (o.cell_width - tw) / 2, y0 + (cell_h - th) / 2, tw, th));
    cv::resize(src, roi, roi.size(), 0, 0, cv::INTER_AREA);
    if (label_h > 0)
      draw_label(mat, labels[i], cv::Rect(x0, y0 + cell_h, o.cell_width, label_h), o.text_colour);
  }
  return sheet;
}

void write_contact_sheet(const std::string& path, const std::vector<Image>& images,
                         const std::vector<std::string>& labels, const ContactSheetOptions& options) {
  write_image(path, make_contact_sheet(images, labels, options));
}

}  // namespace lorgnette::dataset
