#include "clipray/report/SvgPlot.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "clipray/io/XmlText.hpp"

namespace clipray {

namespace {

std::string powerOfTen(int exponent) {
  if (exponent == 0) return "1";
  if (exponent == 1) return "10";
  return "1e" + std::to_string(exponent);
}

// Decades [lo, hi] covering every finite positive value (at least one decade).
struct DecadeRange {
  int lo = 0, hi = 1;
};

DecadeRange decadesOf(const std::vector<double>& values) {
  double minimum = 1e300, maximum = -1e300;
  for (const double v : values) {
    if (v > 0 && std::isfinite(v)) {
      minimum = std::min(minimum, v);
      maximum = std::max(maximum, v);
    }
  }
  if (minimum > maximum) return {};
  DecadeRange range{static_cast<int>(std::floor(std::log10(minimum))),
                    static_cast<int>(std::ceil(std::log10(maximum)))};
  range.hi = std::max(range.hi, range.lo + 1);
  return range;
}

// Sizes of one panel's parts; the overview and the small panels differ only in these.
struct PanelStyle {
  double marginLeft, marginRight, marginTop, marginBottom;
  double nonFiniteBand;  // the "non-finite" line sits this far above the plot area
  double fontSize;
  double markerRadius;
  bool axisTitles;
};

constexpr PanelStyle kOverviewStyle{80, 20, 70, 60, 30, 12, 5, true};
constexpr PanelStyle kSmallStyle{46, 10, 56, 30, 22, 10, 4, false};

// Width of a short label in the SVG's sans-serif font: digits are about 0.6 em wide.
double labelWidth(const std::string& text, double fontSize) {
  return 0.62 * fontSize * static_cast<double>(text.size()) + 2.0;
}

void drawMarker(std::ostringstream& svg, const PlotSeries& series, double x, double y, double r) {
  if (series.shape == MarkerShape::Square) {
    svg << "<rect x=\"" << x - r << "\" y=\"" << y - r << "\" width=\"" << 2 * r << "\" height=\""
        << 2 * r << "\" fill=\"" << series.colour << "\"/>\n";
  } else {
    svg << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"" << r << "\" fill=\""
        << series.colour << "\"/>\n";
  }
}

void drawPanel(std::ostringstream& svg, const SpeedErrorFigure& figure, const LogLogPanel& panel,
               const PlotBox& frame, const PanelStyle& style, DecadeRange xs, DecadeRange ys) {
  const double left = frame.x + style.marginLeft, top = frame.y + style.marginTop;
  const double width = frame.width - style.marginLeft - style.marginRight;
  const double height = frame.height - style.marginTop - style.marginBottom;
  const double nonFiniteY = top - style.nonFiniteBand;
  auto px = [&](double x) { return left + (std::log10(x) - xs.lo) / (xs.hi - xs.lo) * width; };
  auto py = [&](double y) {
    if (!(y > 0) || !std::isfinite(y)) return nonFiniteY;
    return top + height - (std::log10(y) - ys.lo) / (ys.hi - ys.lo) * height;
  };
  const double font = style.fontSize;
  svg << "<g font-size=\"" << font << "\">\n";
  svg << "<text x=\"" << left + width / 2 << "\" y=\"" << frame.y + font + 4
      << "\" text-anchor=\"middle\" font-weight=\"bold\">" << xmlEscaped(panel.title)
      << "</text>\n";
  // A grid line every decade, a tick label every `step` decades so that labels keep clear of
  // each other (about 4 characters wide on x, one line high on y).
  const int xStep = static_cast<int>(std::ceil(3.0 * font / (width / (xs.hi - xs.lo))));
  const int yStep = static_cast<int>(std::ceil(1.3 * font / (height / (ys.hi - ys.lo))));
  for (int e = xs.lo; e <= xs.hi; ++e) {
    const double x = px(std::pow(10.0, e));
    svg << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + height
        << "\" stroke=\"#ddd\"/>\n";
    if ((e - xs.lo) % xStep != 0) continue;
    svg << "<text x=\"" << x << "\" y=\"" << top + height + font + 4 << "\" text-anchor=\"middle\">"
        << powerOfTen(e) << "</text>\n";
  }
  for (int e = ys.lo; e <= ys.hi; ++e) {
    const double y = py(std::pow(10.0, e));
    svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + width << "\" y2=\"" << y
        << "\" stroke=\"#ddd\"/>\n";
    if ((e - ys.lo) % yStep != 0) continue;
    svg << "<text x=\"" << left - 5 << "\" y=\"" << y + font / 3 << "\" text-anchor=\"end\">"
        << powerOfTen(e) << "</text>\n";
  }
  svg << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << width << "\" height=\""
      << height << "\" fill=\"none\" stroke=\"#333\"/>\n";
  svg << "<line x1=\"" << left << "\" y1=\"" << nonFiniteY << "\" x2=\"" << left + width
      << "\" y2=\"" << nonFiniteY << "\" stroke=\"#c00\" stroke-dasharray=\"2,3\"/>\n";
  svg << "<text x=\"" << left - 5 << "\" y=\"" << nonFiniteY + font / 3
      << "\" text-anchor=\"end\" fill=\"#c00\">" << (style.axisTitles ? "non-finite" : "inf")
      << "</text>\n";
  for (const auto& [value, label] : figure.yLines) {
    if (!(value >= std::pow(10.0, ys.lo) && value <= std::pow(10.0, ys.hi))) continue;
    const double y = py(value);
    svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + width << "\" y2=\"" << y
        << "\" stroke=\"#888\" stroke-dasharray=\"6,4\"/>\n";
    if (style.axisTitles) {
      svg << "<text x=\"" << left + width - 4 << "\" y=\"" << y - 4
          << "\" text-anchor=\"end\" fill=\"#555\">" << xmlEscaped(label) << "</text>\n";
    }
  }
  if (style.axisTitles) {
    svg << "<text x=\"" << left + width / 2 << "\" y=\"" << frame.y + frame.height - 14
        << "\" text-anchor=\"middle\">" << xmlEscaped(figure.xLabel) << "</text>\n";
    svg << "<text transform=\"translate(" << frame.x + 20 << "," << top + height / 2
        << ") rotate(-90)\" text-anchor=\"middle\">" << xmlEscaped(figure.yLabel) << "</text>\n";
  }

  std::vector<const PlotPoint*> drawn;
  std::vector<PlotBox> markers;
  std::vector<std::pair<double, double>> sizes;
  const double r = style.markerRadius;
  for (const PlotPoint& p : panel.points) {
    if (!(p.x > 0) || !std::isfinite(p.x) || p.series >= figure.series.size()) continue;
    drawn.push_back(&p);
    markers.push_back({px(p.x) - r, py(p.y) - r, 2 * r, 2 * r});
    sizes.emplace_back(labelWidth(std::to_string(p.key), font), font);
  }
  // Labels may use the plot area, the non-finite band and the margin on the right.
  const PlotBox labelFrame{left, nonFiniteY - style.nonFiniteBand / 2 - font / 2,
                           width + style.marginRight,
                           top + height - (nonFiniteY - style.nonFiniteBand / 2 - font / 2)};
  const std::vector<PlotBox> labels = placeLabels(markers, sizes, labelFrame);
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    const PlotPoint& p = *drawn[i];
    const double x = markers[i].x + r, y = markers[i].y + r;
    drawMarker(svg, figure.series[p.series], x, y, r);
    const PlotBox& label = labels[i];
    if (label.width == 0) continue;
    const double cx = label.x + label.width / 2, cy = label.y + label.height / 2;
    // A leader line once the label sits clear of its own marker's immediate neighbourhood.
    if (std::hypot(cx - x, cy - y) > r + label.width / 2 + label.height / 2 + 4) {
      const double nearX = std::clamp(x, label.x, label.x + label.width);
      const double nearY = std::clamp(y, label.y, label.y + label.height);
      svg << "<line x1=\"" << x << "\" y1=\"" << y << "\" x2=\"" << nearX << "\" y2=\"" << nearY
          << "\" stroke=\"#999\" stroke-width=\"0.7\"/>\n";
    }
    svg << "<text x=\"" << cx << "\" y=\"" << label.y + label.height * 0.85
        << "\" text-anchor=\"middle\">" << p.key << "</text>\n";
  }
  svg << "</g>\n";
}

}  // namespace

std::vector<PlotBox> placeLabels(const std::vector<PlotBox>& markers,
                                 const std::vector<std::pair<double, double>>& labelSizes,
                                 const PlotBox& frame) {
  constexpr int kDirections = 16;
  constexpr double kGaps[] = {1, 4, 9, 16, 26, 40, 58, 80, 110, 150};
  std::vector<PlotBox> placed(markers.size());
  std::vector<PlotBox> taken(markers.begin(), markers.end());
  const auto inside = [&](const PlotBox& box) {
    return box.x >= frame.x && box.y >= frame.y && box.x + box.width <= frame.x + frame.width &&
           box.y + box.height <= frame.y + frame.height;
  };
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const auto [w, h] = labelSizes[i];
    const double cx = markers[i].x + markers[i].width / 2,
                 cy = markers[i].y + markers[i].height / 2;
    const double markerRadius = markers[i].width / 2;
    bool found = false;
    for (const double gap : kGaps) {
      for (int k = 0; k < kDirections && !found; ++k) {
        // Right first, then round both ways: the conventional spot for a point label.
        const int step = (k + 1) / 2 * (k % 2 == 0 ? 1 : -1);
        const double angle = 2.0 * std::numbers::pi * step / kDirections;
        const double dx = std::cos(angle), dy = std::sin(angle);
        // From the label's centre to its edge along the direction, so the gap is edge to edge.
        const double halfExtent = std::min(std::abs(dx) > 1e-9 ? w / 2 / std::abs(dx) : 1e300,
                                           std::abs(dy) > 1e-9 ? h / 2 / std::abs(dy) : 1e300);
        const double distance = markerRadius + gap + halfExtent;
        const PlotBox box{cx + dx * distance - w / 2, cy + dy * distance - h / 2, w, h};
        if (!inside(box)) continue;
        if (std::any_of(taken.begin(), taken.end(),
                        [&](const PlotBox& other) { return box.overlaps(other); })) {
          continue;
        }
        placed[i] = box;
        taken.push_back(box);
        found = true;
      }
      if (found) break;
    }
  }
  return placed;
}

std::string renderSvg(const SpeedErrorFigure& figure) {
  constexpr double kWidth = 1240;
  constexpr double kTitleHeight = 40;
  const PlotBox overviewFrame{0, kTitleHeight, 780, 600};
  constexpr double kKeyX = 800, kKeyRowHeight = 17;
  constexpr int kColumns = 4;
  constexpr double kSmallWidth = kWidth / kColumns, kSmallHeight = 240;

  std::vector<double> xs, ys, caseXs, caseYs;
  for (const PlotPoint& p : figure.overview.points) xs.push_back(p.x), ys.push_back(p.y);
  for (const LogLogPanel& panel : figure.perCase) {
    for (const PlotPoint& p : panel.points) caseXs.push_back(p.x), caseYs.push_back(p.y);
  }
  // The reference lines stay in view.
  for (const auto& line : figure.yLines) ys.push_back(line.first), caseYs.push_back(line.first);

  // Legend (series, reference lines, the non-finite line), then the key table.
  const double legendTop = kTitleHeight + 20;
  const double keyTop = legendTop + 20.0 * static_cast<double>(figure.series.size() + 2) + 24;
  const double keyBottom = keyTop + kKeyRowHeight * static_cast<double>(figure.key.size() + 1);
  const double casesTop = std::max(overviewFrame.y + overviewFrame.height, keyBottom) + 30;
  const auto caseRows = (figure.perCase.size() + kColumns - 1) / kColumns;
  const double height =
      casesTop + (caseRows > 0 ? 30 + kSmallHeight * static_cast<double>(caseRows) : 0) + 10;

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << kWidth << " " << height
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << kWidth / 2 << "\" y=\"26\" text-anchor=\"middle\" font-size=\"17\">"
      << xmlEscaped(figure.title) << "</text>\n";
  drawPanel(svg, figure, figure.overview, overviewFrame, kOverviewStyle, decadesOf(xs),
            decadesOf(ys));

  double y = legendTop;
  svg << "<text x=\"" << kKeyX << "\" y=\"" << y << "\" font-weight=\"bold\">Legend</text>\n";
  for (const PlotSeries& series : figure.series) {
    y += 20;
    drawMarker(svg, series, kKeyX + 8, y - 4, 5);
    svg << "<text x=\"" << kKeyX + 22 << "\" y=\"" << y << "\">" << xmlEscaped(series.name)
        << "</text>\n";
  }
  y += 20;
  svg << "<line x1=\"" << kKeyX << "\" y1=\"" << y - 4 << "\" x2=\"" << kKeyX + 16 << "\" y2=\""
      << y - 4 << "\" stroke=\"#888\" stroke-dasharray=\"6,4\"/>\n";
  svg << "<text x=\"" << kKeyX + 22 << "\" y=\"" << y << "\">reference error (labelled)</text>\n";
  y += 20;
  svg << "<line x1=\"" << kKeyX << "\" y1=\"" << y - 4 << "\" x2=\"" << kKeyX + 16 << "\" y2=\""
      << y - 4 << "\" stroke=\"#c00\" stroke-dasharray=\"2,3\"/>\n";
  svg << "<text x=\"" << kKeyX + 22 << "\" y=\"" << y
      << "\">non-finite rays (NaN or inf) on some case</text>\n";
  y = keyTop;
  svg << "<text x=\"" << kKeyX << "\" y=\"" << y << "\" font-weight=\"bold\">"
      << xmlEscaped(figure.keyTitle) << "</text>\n";
  svg << "<g font-family=\"monospace\" font-size=\"12\">\n";
  for (const PlotKeyEntry& entry : figure.key) {
    y += kKeyRowHeight;
    if (entry.series < figure.series.size()) {
      drawMarker(svg, figure.series[entry.series], kKeyX + 6, y - 4, 4);
    }
    svg << "<text x=\"" << kKeyX + 38 << "\" y=\"" << y << "\" text-anchor=\"end\">" << entry.key
        << "</text>\n";
    svg << "<text x=\"" << kKeyX + 46 << "\" y=\"" << y << "\" xml:space=\"preserve\">"
        << xmlEscaped(entry.text) << "</text>\n";
  }
  svg << "</g>\n";

  if (!figure.perCase.empty()) {
    svg << "<text x=\"" << kWidth / 2 << "\" y=\"" << casesTop + 16
        << "\" text-anchor=\"middle\" font-size=\"15\">Per hard case: " << xmlEscaped(figure.xLabel)
        << " (x) against " << xmlEscaped(figure.yLabel) << " (y), shared axes</text>\n";
    const DecadeRange caseX = decadesOf(caseXs), caseY = decadesOf(caseYs);
    for (std::size_t i = 0; i < figure.perCase.size(); ++i) {
      const PlotBox frame{kSmallWidth * static_cast<double>(i % kColumns),
                          casesTop + 30 + kSmallHeight * static_cast<double>(i / kColumns),
                          kSmallWidth, kSmallHeight};
      drawPanel(svg, figure, figure.perCase[i], frame, kSmallStyle, caseX, caseY);
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace clipray
