// Log-log charts as standalone SVG, drawn without any plotting library: decade grid, labelled points,
// lines through a series, and the Pareto front of a series (the points no other point beats in both
// coordinates), drawn as a dashed staircase.
#pragma once

#include <string>
#include <vector>

namespace humandyn::bench {

struct ChartPoint {
  double x = 0, y = 0;
  std::string label;  // written beside the point when non-empty
};

struct ChartSeries {
  std::string name;  // legend
  std::vector<ChartPoint> points;
  std::string color = "#1f77b4";
  bool connect = false;  // draw a line through the points in order
  bool hollow = false;   // open markers
  bool pareto = false;   // draw this series' Pareto front (smaller x and smaller y are better)
  bool dashed = false;   // dashed connecting line
};

struct Chart {
  std::string title, x_label, y_label;
  std::vector<ChartSeries> series;
  double y_floor = 1e-19;  // values below (e.g. an exact zero) are drawn at this level
};

// The indices of the Pareto-optimal points, by increasing x.
std::vector<std::size_t> pareto_front(const std::vector<ChartPoint>& points);

// The chart as an SVG document.
std::string render_svg(const Chart& chart);

// Writes the chart to `path`; throws std::runtime_error if the file cannot be written.
void write_svg(const Chart& chart, const std::string& path);

}  // namespace humandyn::bench
