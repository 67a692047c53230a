#pragma once
// The pictures of a run beyond its four full-size PNGs (encodeRunImages, Report.hpp): the small
// thumbnails index.html shows for every run, and the enlarged crops around its largest unexplained
// clusters; and the colours all of them use, for the page's legend. Colours and layout are
// documented at the top of Images.cpp.

#include <cstdint>
#include <string>
#include <vector>

#include "clipray/compare/MismatchClusters.hpp"
#include "clipray/compare/Reconcile.hpp"
#include "clipray/report/Report.hpp"

namespace clipray {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// A PNG of width x height RGB pixels, top row first (rgb: 3 bytes a pixel); for pictures drawn
// elsewhere (reconcile --page's picks.png).
std::string encodeRgbPng(int width, int height, const std::vector<std::uint8_t>& rgb);

// mismatch.png's colour of a class.
Rgb pixelClassColour(PixelClass value);
// error_heatmap.png's colour of |d_r - d_a| / tolerance: logarithmic, kHeatMapFloor .. 1 on the
// viridis ramp, 1 .. kHeatMapCeiling red to white; NaN (not compared) black.
Rgb heatMapColour(double ratio);
inline constexpr double kHeatMapFloor = 1e-4;    // and below: the ramp's first colour
inline constexpr double kHeatMapCeiling = 10.0;  // and above: white
// raster_depth.png / ray_depth.png: no hit, and the grey of the farthest and nearest depths.
inline constexpr Rgb kDepthBackground{20, 30, 70};
inline constexpr int kFarGrey = 48;
inline constexpr int kNearGrey = 255;

// Thumbnails are at most this many pixels wide and high: the frame in blocks of f x f pixels, f the
// smallest integer that brings both sides within it.
inline constexpr int kThumbnailSide = 160;
Viewport thumbnailSize(Viewport frame);
// Crops: a window of kCropSide x kCropSide frame pixels (fewer where the frame is smaller), each
// drawn as kCropScale x kCropScale image pixels.
inline constexpr int kCropSide = 32;
inline constexpr int kCropScale = 8;

// The frame pixels a cluster's crop shows, in top-down image coordinates: the window centred on
// the cluster's representative pixel, moved inside the frame.
struct CropWindow {
  int x = 0, y = 0, width = 0, height = 0;
};
CropWindow clusterCropWindow(const MismatchCluster& cluster, Viewport viewport);

// Appends thumb_mismatch.png (each thumbnail pixel the most severe class of its block of frame
// pixels, an unexplained block also painting the eight around it, so one unexplained pixel shows
// as a dot) and thumb_heatmap.png (the block's largest ratio) to run.images.
void encodeThumbnails(RunRecord& run, const PixelComparison& pixels);
// Appends cluster1.png, cluster2.png, ... for run.clusters.largest to run.images: each cluster's
// crop of the mismatch image, enlarged, its representative pixel outlined in white.
void encodeClusterCrops(RunRecord& run, const PixelComparison& pixels);

}  // namespace clipray
