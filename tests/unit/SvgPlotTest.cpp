// The bench plot's label placement and what the SVG holds: no two labels and no label and marker
// overlap, every point is numbered as its key row says, and series differ in shape.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "clipray/report/SvgPlot.hpp"

namespace clipray {
namespace {

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++count;
  }
  return count;
}

TEST(SvgPlot, LabelsNeverOverlapEachOtherOrAnyMarkerEvenWhenPointsCoincide) {
  // 32 markers (16 methods x 2 precisions, more than the bench has), half of them piled on
  // three spots, the rest random: the worst case for a plot whose methods cost the same.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(100, 600);
  std::vector<PlotBox> markers;
  std::vector<std::pair<double, double>> sizes;
  for (int i = 0; i < 32; ++i) {
    const double x = i < 16 ? 200 + 40 * (i % 3) : coordinate(random);
    const double y = i < 16 ? 300 + 1.5 * (i % 2) : coordinate(random);
    markers.push_back({x - 5, y - 5, 10, 10});
    sizes.emplace_back(i + 1 < 10 ? 9.4 : 16.9, 12.0);
  }
  const PlotBox frame{80, 40, 680, 600};
  const std::vector<PlotBox> labels = placeLabels(markers, sizes, frame);
  ASSERT_EQ(labels.size(), markers.size());
  for (std::size_t i = 0; i < labels.size(); ++i) {
    SCOPED_TRACE(i);
    ASSERT_GT(labels[i].width, 0.0) << "label not placed";
    EXPECT_EQ(labels[i].width, sizes[i].first);
    EXPECT_GE(labels[i].x, frame.x);
    EXPECT_GE(labels[i].y, frame.y);
    EXPECT_LE(labels[i].x + labels[i].width, frame.x + frame.width);
    EXPECT_LE(labels[i].y + labels[i].height, frame.y + frame.height);
    for (std::size_t j = 0; j < labels.size(); ++j) {
      if (j != i) {
        EXPECT_FALSE(labels[i].overlaps(labels[j])) << "label " << j;
      }
    }
    for (std::size_t j = 0; j < markers.size(); ++j) {
      EXPECT_FALSE(labels[i].overlaps(markers[j])) << "marker " << j;
    }
  }
  // A lone point takes the spot to the right of its marker, 1 unit clear, centred vertically.
  const std::vector<PlotBox> lone = placeLabels({{100, 100, 10, 10}}, {{9.4, 12}}, frame);
  EXPECT_DOUBLE_EQ(lone[0].x, 111.0);
  EXPECT_DOUBLE_EQ(lone[0].y, 99.0);
}

TEST(SvgPlot, TooManyLabelsForTheFrameAreLeftOutNotPiledUp) {
  std::vector<PlotBox> markers;
  std::vector<std::pair<double, double>> sizes;
  for (int i = 0; i < 40; ++i) {
    markers.push_back({50, 50, 10, 10});
    sizes.emplace_back(10, 12);
  }
  const std::vector<PlotBox> labels = placeLabels(markers, sizes, {0, 0, 100, 100});
  int placed = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i].width == 0) continue;
    ++placed;
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(labels[i].overlaps(labels[j]));
    }
  }
  EXPECT_GT(placed, 10);
  EXPECT_LT(placed, 40);
}

TEST(SvgPlot, FigureHasLegendKeyAndOnePanelPerCase) {
  SpeedErrorFigure figure;
  figure.title = "t";
  figure.xLabel = "ns";
  figure.yLabel = "px";
  figure.series = {{"float", "#1f77b4", MarkerShape::Circle},
                   {"double", "#d62728", MarkerShape::Square}};
  figure.keyTitle = "Key";
  figure.overview.points = {{1, 1.0, 0.5, 0}, {2, 2.0, 1e-9, 1}, {3, 3.0, INFINITY, 0}};
  figure.key = {{1, 0, "a float"}, {2, 1, "a double"}, {3, 0, "b <float>"}};
  for (int c = 0; c < 5; ++c) {
    figure.perCase.push_back({"case " + std::to_string(c), figure.overview.points});
  }
  const std::string svg = renderSvg(figure);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find(">Legend</text>"), std::string::npos);
  EXPECT_NE(svg.find(">float</text>"), std::string::npos);
  EXPECT_NE(svg.find(">double</text>"), std::string::npos);
  EXPECT_NE(svg.find("b &lt;float&gt;"), std::string::npos);
  for (int c = 0; c < 5; ++c) {
    EXPECT_NE(svg.find(">case " + std::to_string(c) + "</text>"), std::string::npos);
  }
  // Six panels of three points: float points are circles (plus 2 in the legend and key),
  // double points squares; every point's key number is drawn.
  EXPECT_EQ(countOf(svg, "<circle"), 6u * 2u + 1u + 2u);
  EXPECT_EQ(countOf(svg, "<rect x="), 6u * 1u + 1u + 1u + 6u);  // plus six plot frames
  EXPECT_EQ(countOf(svg, "text-anchor=\"middle\">3</text>"), 6u);
}

}  // namespace
}  // namespace clipray
