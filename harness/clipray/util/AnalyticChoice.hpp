#pragma once
// How the analytic side finds each pixel's closest hit for clipray's own camera rays: the screen
// path (ScreenEvaluator.hpp: each triangle's coverage and depth decided at the pixel centres, as a
// rasterizer decides them, with bounds that make every decision the ray path's; the pixels the
// bounds cannot decide are traced; a decided pixel keeps its triangle's planes, which the compare
// evaluates in place of a ray), or the ray path (every pixel's robust ray traced through the
// screen bins or the BVH, each hit's t kept). Both hit the same primitives and give every pixel
// the same class; the screen path's depth figures lie within its planes' bound of the ray path's.
// Auto, the default, takes the screen path where the frame has at least kScreenPixelsPerTriangle
// pixels for each triangle (below that, setting up every triangle costs more than tracing the
// pixels: docs/performance.md). An app's own picking rays always go through the ray path.
// Process-wide: choose before a reconcile starts, never while one runs (`--analytic`).

#include <optional>
#include <string_view>

namespace clipray {

enum class AnalyticPath { Auto, Rays, Screen };

// Where Auto takes the screen path: measured on the 100k-triangle terrain, one thread (the
// intersect phase's CPU, rays against screen: 17.5 against 35.6 ms at 480x270, 1.3 pixels a
// triangle; 29.4 against 46.6 at 960x540, 5.2; 68.4 against 69.1 at 1920x1080, 20.7; a small scene
// of a few thousand triangles at 1080p, 41 against 13).
inline constexpr double kScreenPixelsPerTriangle = 16.0;

void chooseAnalyticPath(AnalyticPath path);
AnalyticPath chosenAnalyticPath();

std::string_view analyticPathName(AnalyticPath path);  // "auto", "rays", "screen"
// The path a name gives; nullopt for any other name.
std::optional<AnalyticPath> analyticPathNamed(std::string_view name);

}  // namespace clipray
