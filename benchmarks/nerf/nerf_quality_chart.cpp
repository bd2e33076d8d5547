// One chart from several nerf_quality_bench runs: reads their <label>_quality.csv files and draws
// held-out PSNR against a chosen column (steps, seconds, samples or cpu_s), one line per run, so
// configurations trained one after the other compare on one picture (docs/bench/nerf.md).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "host/util/chart.h"

using namespace lorgnette;

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  return cells;
}

// The run's label: the file name without "_quality.csv".
std::string label_of(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  const std::string suffix = "_quality.csv";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  return name;
}

ChartSeries read_series(const std::string& path, const std::string& x_column) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read '" + path + "': give the CSV files nerf_quality_bench wrote");
  std::string line;
  if (!std::getline(in, line))
    throw std::runtime_error("'" + path + "' is empty: the run wrote no checkpoint");
  const std::vector<std::string> header = split_csv_line(line);
  auto column = [&](const std::string& name) {
    auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end())
      throw std::runtime_error(
          fmt::format("'{}' has no column '{}' (its columns: {})", path, name, fmt::join(header, ", ")));
    return size_t(it - header.begin());
  };
  const size_t xi = column(x_column), yi = column("psnr");
  ChartSeries s{label_of(path), {}, {}};
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() <= std::max(xi, yi))
      throw std::runtime_error(
          fmt::format("'{}' line {} has {} cells, the header {}", path, row, cells.size(), header.size()));
    s.x.push_back(std::stod(cells[xi]));
    s.y.push_back(std::stod(cells[yi]));
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Held-out PSNR of several nerf_quality_bench runs on one chart"};
  std::vector<std::string> csvs;
  std::string out, x_column = "steps", title = "held-out PSNR";
  app.add_option("csv", csvs, "<label>_quality.csv files")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out, "PNG to write")->required();
  app.add_option("--x", x_column, "column for the x axis")
      ->check(CLI::IsMember({"steps", "seconds", "samples", "cpu_s"}));
  app.add_option("--title", title);
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<ChartSeries> series;
    for (const std::string& path : csvs) series.push_back(read_series(path, x_column));
    const std::string x_label = x_column == "cpu_s" ? "training CPU seconds" : "training " + x_column;
    write_chart(out, {title, x_label, "PSNR (dB)"}, series);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
