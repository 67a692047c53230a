#pragma once
// How the analytic side finds each pixel's closest hit for clipray's own camera rays: the screen
// path, the default (ScreenEvaluator.hpp: each triangle's coverage and depth decided at the pixel
// centres, as a rasterizer decides them, with bounds that make every decision the ray path's; the
// pixels the bounds cannot decide are traced; a decided pixel keeps its triangle's planes, which
// the compare evaluates in place of a ray), or the ray path (every pixel's robust ray traced
// through the screen bins or the BVH, each hit's t kept). Both hit the same primitives and give
// every pixel the same class; the screen path's depth figures lie within its planes' bound of the
// ray path's. An app's own picking rays always go through the ray path. Process-wide: choose
// before a reconcile starts, never while one runs (`clipray reconcile --analytic`).

#include <optional>
#include <string_view>

namespace clipray {

enum class AnalyticPath { Rays, Screen };

void chooseAnalyticPath(AnalyticPath path);
AnalyticPath chosenAnalyticPath();

std::string_view analyticPathName(AnalyticPath path);  // "rays", "screen"
// The path a name gives; nullopt for any other name.
std::optional<AnalyticPath> analyticPathNamed(std::string_view name);

}  // namespace clipray
