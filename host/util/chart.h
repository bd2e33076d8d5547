// Small line/scatter charts as PNG (OpenCV drawing), for benchmarks and reports: every benchmark
// writes its CSV and a chart with this, so no plotting toolchain is needed on the machine.
#pragma once
#include <string>
#include <vector>

namespace lorgnette {

struct ChartSeries {
  std::string name;
  std::vector<double> x, y;
  bool points_only = false;  // scatter instead of a polyline
};

struct ChartSpec {
  std::string title, x_label, y_label;
  bool log_x = false;
  int width = 900, height = 560;
};

// Writes a PNG chart; throws std::runtime_error when it cannot write.
void write_chart(const std::string& path, const ChartSpec& spec, const std::vector<ChartSeries>& series);

// Writes rows as CSV (header first); values are written with full precision.
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows);

}  // namespace lorgnette
