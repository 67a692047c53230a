#pragma once
// A log-log scatter plot as a standalone SVG (opens in any browser): `clipray bench --plot` draws
// speed (ns per ray) against worst error (pixels), one labelled point per method x precision.

#include <string>
#include <vector>

namespace clipray {

struct PlotPoint {
  std::string label;
  double x = 0.0;  // > 0 (log axis)
  double y = 0.0;  // > 0; +inf / NaN are drawn on a "non-finite" line above the plot
  std::string colour = "#1f77b4";
};

struct LogLogPlot {
  std::string title;
  std::string xLabel;
  std::string yLabel;
  std::vector<PlotPoint> points;
  // Horizontal reference lines (e.g. "1 px"), drawn dashed when inside the range.
  std::vector<std::pair<double, std::string>> yLines;
};

std::string renderSvg(const LogLogPlot& plot);

}  // namespace clipray
