#include "clipray/report/SvgPlot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace clipray {

namespace {

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string powerOfTen(int exponent) {
  if (exponent == 0) return "1";
  if (exponent == 1) return "10";
  return "1e" + std::to_string(exponent);
}

}  // namespace

std::string renderSvg(const LogLogPlot& plot) {
  constexpr double kWidth = 900, kHeight = 620;
  constexpr double kLeft = 90, kRight = 40, kTop = 80, kBottom = 70;
  const double plotWidth = kWidth - kLeft - kRight, plotHeight = kHeight - kTop - kBottom;

  double xMin = 1e300, xMax = -1e300, yMin = 1e300, yMax = -1e300;
  for (const PlotPoint& p : plot.points) {
    if (p.x > 0 && std::isfinite(p.x)) {
      xMin = std::min(xMin, p.x);
      xMax = std::max(xMax, p.x);
    }
    if (p.y > 0 && std::isfinite(p.y)) {
      yMin = std::min(yMin, p.y);
      yMax = std::max(yMax, p.y);
    }
  }
  if (xMin > xMax) xMin = 1, xMax = 10;
  if (yMin > yMax) yMin = 1, yMax = 10;
  const int x0 = static_cast<int>(std::floor(std::log10(xMin))),
            x1 = std::max(x0 + 1, static_cast<int>(std::ceil(std::log10(xMax))));
  const int y0 = static_cast<int>(std::floor(std::log10(yMin))),
            y1 = std::max(y0 + 1, static_cast<int>(std::ceil(std::log10(yMax))));
  auto px = [&](double x) { return kLeft + (std::log10(x) - x0) / (x1 - x0) * plotWidth; };
  auto py = [&](double y) {
    if (!(y > 0) || !std::isfinite(y)) return kTop - 30.0;  // the non-finite line
    return kTop + plotHeight - (std::log10(y) - y0) / (y1 - y0) * plotHeight;
  };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << " " << kHeight
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << kWidth / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">"
      << escape(plot.title) << "</text>\n";
  // Grid and ticks, one per decade.
  for (int e = x0; e <= x1; ++e) {
    const double x = px(std::pow(10.0, e));
    svg << "<line x1=\"" << x << "\" y1=\"" << kTop << "\" x2=\"" << x << "\" y2=\""
        << kTop + plotHeight << "\" stroke=\"#ddd\"/>\n";
    svg << "<text x=\"" << x << "\" y=\"" << kTop + plotHeight + 18 << "\" text-anchor=\"middle\">"
        << powerOfTen(e) << "</text>\n";
  }
  for (int e = y0; e <= y1; ++e) {
    const double y = py(std::pow(10.0, e));
    svg << "<line x1=\"" << kLeft << "\" y1=\"" << y << "\" x2=\"" << kLeft + plotWidth
        << "\" y2=\"" << y << "\" stroke=\"#ddd\"/>\n";
    svg << "<text x=\"" << kLeft - 8 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
        << powerOfTen(e) << "</text>\n";
  }
  svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << plotWidth << "\" height=\""
      << plotHeight << "\" fill=\"none\" stroke=\"#333\"/>\n";
  svg << "<line x1=\"" << kLeft << "\" y1=\"" << kTop - 30 << "\" x2=\"" << kLeft + plotWidth
      << "\" y2=\"" << kTop - 30 << "\" stroke=\"#c00\" stroke-dasharray=\"2,3\"/>\n";
  svg << "<text x=\"" << kLeft - 8 << "\" y=\"" << kTop - 26
      << "\" text-anchor=\"end\" fill=\"#c00\">non-finite</text>\n";
  for (const auto& [value, label] : plot.yLines) {
    if (!(value >= std::pow(10.0, y0) && value <= std::pow(10.0, y1))) continue;
    const double y = py(value);
    svg << "<line x1=\"" << kLeft << "\" y1=\"" << y << "\" x2=\"" << kLeft + plotWidth
        << "\" y2=\"" << y << "\" stroke=\"#888\" stroke-dasharray=\"6,4\"/>\n";
    svg << "<text x=\"" << kLeft + plotWidth - 4 << "\" y=\"" << y - 4
        << "\" text-anchor=\"end\" fill=\"#555\">" << escape(label) << "</text>\n";
  }
  svg << "<text x=\"" << kLeft + plotWidth / 2 << "\" y=\"" << kHeight - 20
      << "\" text-anchor=\"middle\">" << escape(plot.xLabel) << "</text>\n";
  svg << "<text transform=\"translate(22," << kTop + plotHeight / 2
      << ") rotate(-90)\" text-anchor=\"middle\">" << escape(plot.yLabel) << "</text>\n";
  for (const PlotPoint& p : plot.points) {
    if (!(p.x > 0) || !std::isfinite(p.x)) continue;
    const double x = px(p.x), y = py(p.y);
    svg << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"5\" fill=\"" << p.colour
        << "\"><title>" << escape(p.label) << "</title></circle>\n";
    svg << "<text x=\"" << x + 8 << "\" y=\"" << y - 6 << "\">" << escape(p.label) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace clipray
