#pragma once
// How the analytic side finds each pixel's closest hit for clipray's own camera rays: the ray path
// (every pixel's robust ray traced through the screen bins or the BVH), or the screen path
// (ScreenEvaluator.hpp: each triangle's coverage and depth decided at the pixel centres, as a
// rasterizer decides them, with bounds that make every decision the ray path's; the pixels the
// bounds cannot decide are traced). Both give the same hits bit for bit. An app's own picking
// rays always go through the ray path. Process-wide: choose before a reconcile starts, never
// while one runs (`clipray reconcile --analytic`).

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
