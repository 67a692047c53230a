#pragma once
// Speed against error as a standalone SVG (opens in any browser), written by `clipray bench
// --plot`: a log-log overview (one point per method x precision), a key table beside it, and one
// small log-log panel per hard case below, all on shared axes. Points carry a key number instead
// of a name; the numbers are placed so that no two labels and no label and marker overlap, and
// the table says which method each number is. Series (float, double) differ in colour and shape.

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace clipray {

enum class MarkerShape { Circle, Square };

struct PlotSeries {
  std::string name;  // "float"
  std::string colour;
  MarkerShape shape = MarkerShape::Circle;
};

struct PlotPoint {
  int key = 0;     // the number drawn beside the marker, and its row in the key table
  double x = 0.0;  // > 0 (log axis); other values are not drawn
  double y = 0.0;  // > 0; +inf / NaN are drawn on a "non-finite" line above the plot
  std::size_t series = 0;
};

struct LogLogPanel {
  std::string title;
  std::vector<PlotPoint> points;
};

struct PlotKeyEntry {
  int key = 0;
  std::size_t series = 0;
  std::string text;  // "robust float   0.91 ns   0.37 px"
};

struct SpeedErrorFigure {
  std::string title;
  std::string xLabel, yLabel;
  std::vector<PlotSeries> series;
  // Horizontal reference lines (e.g. "1 px"), drawn dashed where inside the range.
  std::vector<std::pair<double, std::string>> yLines;
  LogLogPanel overview;
  std::string keyTitle;
  std::vector<PlotKeyEntry> key;
  std::vector<LogLogPanel> perCase;
};

// An axis-aligned box in SVG coordinates (y down).
struct PlotBox {
  double x = 0, y = 0, width = 0, height = 0;
  bool overlaps(const PlotBox& other) const {
    return x < other.x + other.width && other.x < x + width && y < other.y + other.height &&
           other.y < y + height;
  }
};

// Where each label goes: markers[i] is the box of point i's marker, labelSizes[i] its label's
// width and height. Each label is tried at growing distances in 16 directions and takes the first
// spot inside `frame` that overlaps no marker and no label placed before it. A label that finds
// none (only with far more points than a bench has) gets an empty box and is not drawn.
std::vector<PlotBox> placeLabels(const std::vector<PlotBox>& markers,
                                 const std::vector<std::pair<double, double>>& labelSizes,
                                 const PlotBox& frame);

std::string renderSvg(const SpeedErrorFigure& figure);

}  // namespace clipray
