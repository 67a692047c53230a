// `clipray reconcile --page` (PageReconcile.hpp): the picks the page's Raycaster made, set
// against the page's depth buffer.
//
// The tolerance of one pick, in window depth (derived below, each term a bound):
//   quantization   the stored depth: one step of a 24-bit (2^-24) or 16-bit (2^-16) fixed-point
//                  buffer (GL ES 3.0, 2.13.1: converted to fixed point, rounding either way), or
//                  2 ulp of a 32F one (2^-23 |d|); the R32F copy PageRecorder reads holds a
//                  24-bit value exactly (24 bits fit float32's significand);
//   transform      the vertex shader's float32 arithmetic: three.js uploads projectionMatrix and
//                  modelViewMatrix as float32 and the GPU computes P (MV p). Each product of a
//                  4-term dot product with its entries rounded to float32 errs by at most
//                  gamma_5 = 5u / (1 - 5u) times the sum of its terms' magnitudes (u = 2^-24,
//                  Higham, Accuracy and Stability, 3.1), so with e = V p (the hit in eye space;
//                  V p stands for MV times the object's vertex: the same point)
//                    |de_k| <= g5 sum_j |V_kj| |p_j|,
//                    |dc_r| <= g5 sum_k |P_rk| |e_k| + sum_k |P_rk| |de_k|   (r = z, w),
//                  and z/w, one more rounding: |d(z/w)| <= (|dz| + |z/w| |dw|) / |w| + u |z/w|;
//                  times the window scale (far - near of depthRange, halved under [-1, 1]);
//   interpolation  the rasterizer's interpolation of depth at the pixel centre: 4u (a
//                  barycentric sum of three terms below 1);
//   snapping       GL snaps window positions to 2^-SUBPIXEL_BITS of a pixel (the page's value;
//                  4 is ES 3.0's least): each vertex moves at most half a step in x and in y, so
//                  the surface's depth at the centre moves at most (|dd/dx| + |dd/dy|) 2^-bits / 2,
//                  with the depth's slope per pixel measured on the hit triangle's plane.
// The hit point itself is three.js's, in float64 from float32 positions: its error is far below
// these. A ray through the plane at a grazing angle has an unbounded slope: its tolerance is
// infinite and the pick agrees (the depth there is not determined by the pixel centre).

#include "clipray/page/PageReconcile.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckText.hpp"
#include "clipray/page/DevToolsPipe.hpp"
#include "clipray/page/PageToggle.hpp"

namespace clipray::page {

namespace {

constexpr double kUnit = 0x1p-24;  // float32's unit roundoff
constexpr double kGamma5 = 5 * kUnit / (1 - 5 * kUnit);
constexpr auto kPickTimeout = std::chrono::seconds(30);
constexpr unsigned kZeroToOne = 0x935F;  // GL_ZERO_TO_ONE (EXT_clip_control's ZERO_TO_ONE_EXT)

using Matrix = std::array<double, 16>;  // column-major, as three.js's elements
using Vec4 = std::array<double, 4>;

Matrix matrixOf(const nlohmann::json& elements, const std::string& what) {
  if (!elements.is_array() || elements.size() != 16) {
    throw InputError("the page's camera has no " + what + " matrix");
  }
  Matrix m{};
  for (int k = 0; k < 16; ++k) m[static_cast<std::size_t>(k)] = elements[k].get<double>();
  return m;
}

double at(const Matrix& m, int row, int column) {
  return m[static_cast<std::size_t>(column * 4 + row)];
}

Vec4 times(const Matrix& m, const Vec4& v) {
  Vec4 out{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      out[static_cast<std::size_t>(r)] += at(m, r, c) * v[static_cast<std::size_t>(c)];
  }
  return out;
}

Matrix product(const Matrix& a, const Matrix& b) {
  Matrix out{};
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += at(a, r, k) * at(b, k, c);
      out[static_cast<std::size_t>(c * 4 + r)] = sum;
    }
  }
  return out;
}

// Gauss-Jordan with partial pivoting; nullopt for a singular matrix.
std::optional<Matrix> inverse(const Matrix& m) {
  double a[4][8];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      a[r][c] = at(m, r, c);
      a[r][c + 4] = r == c ? 1.0 : 0.0;
    }
  }
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r) {
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    }
    if (a[pivot][c] == 0.0) return std::nullopt;
    for (int k = 0; k < 8; ++k) std::swap(a[c][k], a[pivot][k]);
    const double scale = a[c][c];
    for (int k = 0; k < 8; ++k) a[c][k] /= scale;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double factor = a[r][c];
      for (int k = 0; k < 8; ++k) a[r][k] -= factor * a[c][k];
    }
  }
  Matrix out{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(c * 4 + r)] = a[r][c + 4];
  }
  return out;
}

// The page's depth state: window depth from clip coordinates.
struct DepthMapping {
  bool zeroToOne = false;
  double rangeNear = 0.0, rangeFar = 1.0;
  double scale() const { return zeroToOne ? rangeFar - rangeNear : (rangeFar - rangeNear) / 2; }
  double window(double ndcZ) const {
    return zeroToOne ? rangeNear + (rangeFar - rangeNear) * ndcZ
                     : rangeNear + (rangeFar - rangeNear) * (ndcZ + 1) / 2;
  }
};

// The value of a Runtime.evaluate answer; nullopt where the expression threw.
std::optional<nlohmann::json> evaluated(const nlohmann::json& answer) {
  if (answer.contains("exceptionDetails") || !answer.contains("result")) return std::nullopt;
  return answer["result"].value("value", nlohmann::json());
}

std::string stateCheckCounts(const PageCheckResult& check) {
  std::size_t errors = 0, warnings = 0, notes = 0;
  const auto count = [&](const std::vector<Finding>& findings) {
    for (const Finding& f : findings) {
      if (f.severity == "error") ++errors;
      if (f.severity == "warning") ++warnings;
      if (f.severity == "note") ++notes;
    }
  };
  for (const CanvasCheck& canvas : check.canvases) {
    if (!canvas.result) continue;
    count(canvas.result->findings);
    for (const trace::TracePairGroup& group : canvas.result->groups) count(group.report.findings);
  }
  std::string text = std::to_string(errors) + " errors, " + std::to_string(warnings) +
                     " warnings, " + std::to_string(notes) + " notes";
  for (const CanvasCheck& canvas : check.canvases) {
    if (!canvas.result) text += "; " + canvas.name + " not checked: " + canvas.notChecked;
  }
  return text;
}

// Window depth of a world point, and its float32 error bound (the transform term above).
struct Projected {
  double depth = 0.0, transformBound = 0.0;
  bool inFront = false;  // w > 0
};

Projected project(const Matrix& projection, const Matrix& view, const DepthMapping& mapping,
                  const std::array<double, 3>& point) {
  const Vec4 p = {point[0], point[1], point[2], 1.0};
  Vec4 eye{}, eyeBound{};
  for (int k = 0; k < 4; ++k) {
    double magnitude = 0.0;
    for (int j = 0; j < 4; ++j) {
      eye[static_cast<std::size_t>(k)] += at(view, k, j) * p[static_cast<std::size_t>(j)];
      magnitude += std::abs(at(view, k, j) * p[static_cast<std::size_t>(j)]);
    }
    eyeBound[static_cast<std::size_t>(k)] = kGamma5 * magnitude;
  }
  const auto clipRow = [&](int r, double& bound) {
    double value = 0.0, magnitude = 0.0, carried = 0.0;
    for (int k = 0; k < 4; ++k) {
      value += at(projection, r, k) * eye[static_cast<std::size_t>(k)];
      magnitude += std::abs(at(projection, r, k) * eye[static_cast<std::size_t>(k)]);
      carried += std::abs(at(projection, r, k)) * eyeBound[static_cast<std::size_t>(k)];
    }
    bound = kGamma5 * magnitude + carried;
    return value;
  };
  double zBound = 0.0, wBound = 0.0;
  const double z = clipRow(2, zBound), w = clipRow(3, wBound);
  Projected out;
  out.inFront = w > 0.0;
  const double ndc = z / w;
  out.depth = mapping.window(ndc);
  out.transformBound =
      mapping.scale() * ((zBound + std::abs(ndc) * wBound) / std::abs(w) + kUnit * std::abs(ndc));
  return out;
}

// The window depth of the plane (point, normal) seen through the pixel centre (x, y) (y from the
// top); NaN where the ray runs along the plane.
double planeDepthAt(const Matrix& clipFromWorld, const Matrix& worldFromClip,
                    const DepthMapping& mapping, int width, int height, double x, double y,
                    const std::array<double, 3>& point, const std::array<double, 3>& normal) {
  const double ndcX = x / width * 2 - 1, ndcY = 1 - y / height * 2;
  // Two points on the pixel's line of sight, inside either convention's clip volume.
  const double z0 = mapping.zeroToOne ? 0.25 : -0.5, z1 = mapping.zeroToOne ? 0.75 : 0.5;
  const Vec4 a = times(worldFromClip, {ndcX, ndcY, z0, 1.0});
  const Vec4 b = times(worldFromClip, {ndcX, ndcY, z1, 1.0});
  if (a[3] == 0.0 || b[3] == 0.0) return std::numeric_limits<double>::quiet_NaN();
  std::array<double, 3> from{}, direction{};
  for (int k = 0; k < 3; ++k) {
    from[static_cast<std::size_t>(k)] = a[static_cast<std::size_t>(k)] / a[3];
    direction[static_cast<std::size_t>(k)] =
        b[static_cast<std::size_t>(k)] / b[3] - from[static_cast<std::size_t>(k)];
  }
  double along = 0.0, offset = 0.0;
  for (int k = 0; k < 3; ++k) {
    const auto i = static_cast<std::size_t>(k);
    along += direction[i] * normal[i];
    offset += (point[i] - from[i]) * normal[i];
  }
  double length = 0.0;
  for (double d : direction) length += d * d;
  // Within a millionth of a radian of the plane: grazing.
  if (std::abs(along) <= 1e-6 * std::sqrt(length)) return std::numeric_limits<double>::quiet_NaN();
  const double t = offset / along;
  const Vec4 hit = {from[0] + t * direction[0], from[1] + t * direction[1],
                    from[2] + t * direction[2], 1.0};
  const Vec4 clip = times(clipFromWorld, hit);
  return mapping.window(clip[2] / clip[3]);
}

double quantizationStep(const std::string& format, double depth) {
  if (format.find("32F") != std::string::npos) return 2 * 0x1p-23 * std::abs(depth) + 0x1p-149;
  if (format.find("16") != std::string::npos) return 0x1p-16;
  return 0x1p-24;
}

const char* kindName(PagePick::Kind kind) {
  switch (kind) {
    case PagePick::Kind::Agree:
      return "agree";
    case PagePick::Kind::DepthBeyondTolerance:
      return "depth-beyond-tolerance";
    case PagePick::Kind::RayOnly:
      return "ray-only";
    case PagePick::Kind::RasterOnly:
      return "raster-only";
  }
  return "";
}

void classify(PageReconcileResult& result, const nlohmann::json& answer) {
  const Matrix projection =
      matrixOf(answer["camera"].value("projection", nlohmann::json()), "projection");
  const Matrix view = matrixOf(answer["camera"].value("view", nlohmann::json()), "view");
  const Matrix clipFromWorld = product(projection, view);
  const std::optional<Matrix> worldFromClip = inverse(clipFromWorld);
  if (!worldFromClip)
    throw InputError(result.check.page + ": the camera's projection * view is singular");
  DepthMapping mapping;
  mapping.zeroToOne = answer.value("clipDepth", 0u) == kZeroToOne;
  mapping.rangeNear = result.depthRangeNear;
  mapping.rangeFar = result.depthRangeFar;

  const nlohmann::json& image = answer["depth"];
  if (!image.is_object() || image.contains("failure")) {
    throw InputError(result.check.page + ": the depth buffer could not be read (" +
                     (image.is_object() ? image.value("failure", "") : std::string("no image")) +
                     ")");
  }
  const int width = image.value("width", 0), height = image.value("height", 0);
  const auto bytes = base64Decoded(image.value("depth", ""));
  const auto pixels =
      static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  if (!bytes || pixels == 0 || bytes->size() != pixels * sizeof(float) || width != result.width ||
      height != result.height) {
    throw InputError(result.check.page + ": the depth image read back is not " +
                     std::to_string(result.width) + "x" + std::to_string(result.height) +
                     " floats");
  }
  std::vector<float> depth(pixels);
  std::memcpy(depth.data(), bytes->data(), bytes->size());
  result.depthFormat = image.value("format", "");

  const double snap = std::ldexp(1.0, -result.subpixelBits) / 2;
  const nlohmann::json& objects = answer["objects"];
  for (const nlohmann::json& entry : answer["picks"]) {
    PagePick pick;
    pick.x = entry[0].get<int>();
    pick.y = entry[1].get<int>();
    pick.ambiguous = entry[3].get<bool>();
    if (pick.x < 0 || pick.y < 0 || pick.x >= width || pick.y >= height) continue;
    // The image's rows run from the bottom.
    const std::size_t index =
        static_cast<std::size_t>(height - 1 - pick.y) * static_cast<std::size_t>(width) +
        static_cast<std::size_t>(pick.x);
    pick.bufferDepth = depth[index];
    const double cleared = std::clamp(result.clearDepth, 0.0, 1.0);
    pick.surface =
        std::abs(pick.bufferDepth - cleared) > quantizationStep(result.depthFormat, cleared);
    const nlohmann::json& hit = entry[2];
    pick.hit = hit.is_array() && hit.size() == 7;
    if (pick.hit) {
      const std::array<double, 3> point = {hit[0].get<double>(), hit[1].get<double>(),
                                           hit[2].get<double>()};
      const std::array<double, 3> normal = {hit[3].get<double>(), hit[4].get<double>(),
                                            hit[5].get<double>()};
      const auto object = hit[6].get<std::size_t>();
      pick.object = object < objects.size() ? objects[object].get<std::string>() : "";
      const Projected projected = project(projection, view, mapping, point);
      pick.rayDepth = projected.depth;
      const double cx = pick.x + 0.5, cy = pick.y + 0.5;
      const double right = planeDepthAt(clipFromWorld, *worldFromClip, mapping, width, height,
                                        cx + 1, cy, point, normal);
      const double below = planeDepthAt(clipFromWorld, *worldFromClip, mapping, width, height, cx,
                                        cy + 1, point, normal);
      const double slope = std::abs(right - projected.depth) + std::abs(below - projected.depth);
      pick.tolerance = std::isfinite(slope)
                           ? quantizationStep(result.depthFormat, pick.bufferDepth) +
                                 projected.transformBound + 4 * kUnit + slope * snap
                           : std::numeric_limits<double>::infinity();
    }
    if (pick.hit && pick.surface) {
      pick.kind = std::abs(pick.rayDepth - pick.bufferDepth) <= pick.tolerance
                      ? PagePick::Kind::Agree
                      : PagePick::Kind::DepthBeyondTolerance;
    } else if (pick.hit) {
      pick.kind = PagePick::Kind::RayOnly;
    } else if (pick.surface) {
      pick.kind = PagePick::Kind::RasterOnly;
    }
    if (pick.kind == PagePick::Kind::Agree) pick.ambiguous = false;
    result.picks.push_back(std::move(pick));
  }
}

std::string clipDepthName(unsigned value) {
  return value == kZeroToOne ? "zero-to-one" : "negative-one-to-one";
}

std::string number(double value) {
  return detail::checkNumber(value);
}

}  // namespace

PageReconcileResult::Counts PageReconcileResult::counts() const {
  Counts c;
  for (const PagePick& pick : picks) {
    switch (pick.kind) {
      case PagePick::Kind::Agree:
        ++(pick.hit ? c.agreeSurface : c.agreeBackground);
        break;
      case PagePick::Kind::DepthBeyondTolerance:
        ++(pick.ambiguous ? c.depthEdge : c.depthUnexplained);
        break;
      case PagePick::Kind::RayOnly:
        ++(pick.ambiguous ? c.rayOnlyEdge : c.rayOnlyUnexplained);
        break;
      case PagePick::Kind::RasterOnly:
        ++(pick.ambiguous ? c.rasterOnlyEdge : c.rasterOnlyUnexplained);
        break;
    }
  }
  return c;
}

double PageReconcileResult::maxDepthError() const {
  double worst = 0.0;
  for (const PagePick& pick : picks) {
    if (pick.hit && pick.surface && !pick.ambiguous) {
      worst = std::max(worst, std::abs(pick.rayDepth - pick.bufferDepth));
    }
  }
  return worst;
}

double PageReconcileResult::maxErrorOverTolerance() const {
  double worst = 0.0;
  for (const PagePick& pick : picks) {
    if (pick.hit && pick.surface && !pick.ambiguous && std::isfinite(pick.tolerance) &&
        pick.tolerance > 0) {
      worst = std::max(worst, std::abs(pick.rayDepth - pick.bufferDepth) / pick.tolerance);
    }
  }
  return worst;
}

bool PageReconcileResult::consistent() const {
  const Counts c = counts();
  return c.depthUnexplained == 0 && c.rayOnlyUnexplained == 0 && c.rasterOnlyUnexplained == 0;
}

bool PageReconcileResult::allConsistent() const {
  return consistent() && toggle.failed.empty() && (!toggle.run || toggle.run->consistent());
}

const char* pagePickClassName(PagePick::Kind kind) {
  return kindName(kind);
}

std::string pageStateCheckCounts(const PageCheckResult& check) {
  return stateCheckCounts(check);
}

namespace {

// The picks of one load: finds the page's three.js and runs its Raycaster (PageRecorder.cpp's
// findThree and pick); the answer, or InputError.
nlohmann::json pickAnswer(DevToolsPipe& browser, const std::string& session,
                          const PageCheckResult& check, const PageReconcileOptions& options) {
  const std::string page = check.page;
  const auto deadline = Clock::now() + kPickTimeout;
  std::string why;
  try {
    // import() is the evaluation's own: the page's import map applies to it.
    const auto found = evaluated(
        browser.call("Runtime.evaluate",
                     {{"expression", "__clipray.findThree((specifier) => import(specifier))"},
                      {"awaitPromise", true},
                      {"returnByValue", true}},
                     session, deadline));
    why = found && found->is_string() ? found->get<std::string>() : "the page did not answer";
  } catch (const DevToolsPipe::TimedOut&) {
    why = "the page did not answer in " + std::to_string(kPickTimeout.count()) + " s";
  }
  if (!why.empty()) {
    throw InputError(page + ": no three.js picking to reconcile (" + why +
                     "); picking skipped; the state check found " + stateCheckCounts(check) +
                     " (clipray check --page tells them)");
  }
  nlohmann::json answer;
  try {
    const auto picked =
        evaluated(browser.call("Runtime.evaluate",
                               {{"expression", "__clipray.pick(" + std::to_string(options.columns) +
                                                   ", " + std::to_string(options.rows) + ")"},
                                {"returnByValue", true}},
                               session, deadline));
    if (picked && picked->is_string()) {
      answer = nlohmann::json::parse(picked->get<std::string>(), nullptr, false);
    }
  } catch (const DevToolsPipe::TimedOut&) {
    throw InputError(page + ": the picks did not finish in " +
                     std::to_string(kPickTimeout.count()) + " s");
  }
  if (!answer.is_object() || answer.contains("failure")) {
    throw InputError(page + ": the page's Raycaster could not be run" +
                     (answer.is_object() ? " (" + answer.value("failure", "") + ")" : ""));
  }
  return answer;
}

// One load of the page, picked and classified.
PageReconcileResult reconcileLoad(PageBrowser& browser, const PageReconcileOptions& options,
                                  bool toggled, nlohmann::json& toggleFacts) {
  PageOptions pageOptions = options.page;
  // The depth buffer must outlive the frame and be single-sampled (--verify's contexts).
  pageOptions.verify = true;
  pageOptions.three = true;
  pageOptions.toggleReversedDepth = toggled;
  nlohmann::json answer;
  PageReconcileResult result;
  result.check = browser.load(
      pageOptions, [&](DevToolsPipe& pipe, const std::string& session, PageCheckResult& check) {
        answer = pickAnswer(pipe, session, check, options);
      });
  result.toggled = toggled;
  result.revision = answer.value("revision", "");
  result.canvas = answer.value("canvas", "");
  result.width = answer.value("width", 0);
  result.height = answer.value("height", 0);
  result.cssWidth = answer.value("cssWidth", 0.0);
  result.cssHeight = answer.value("cssHeight", 0.0);
  result.devicePixelRatio = answer.value("devicePixelRatio", 1.0);
  result.columns = options.columns;
  result.rows = options.rows;
  result.camera = answer["camera"];
  result.reversedDepthBuffer = answer.value("reversedDepthBuffer", false);
  result.clipDepth = clipDepthName(answer.value("clipDepth", 0u));
  result.clearDepth = answer.value("clearDepth", 1.0);
  const nlohmann::json range = answer.value("depthRange", nlohmann::json::array({0.0, 1.0}));
  result.depthRangeNear = range.size() == 2 ? range[0].get<double>() : 0.0;
  result.depthRangeFar = range.size() == 2 ? range[1].get<double>() : 1.0;
  result.subpixelBits = answer.value("subpixelBits", 4);
  toggleFacts = answer.value("toggle", nlohmann::json::object());
  classify(result, answer);
  return result;
}

}  // namespace

PageReconcileResult reconcilePage(const PageReconcileOptions& options) {
  if (options.columns < 1 || options.rows < 1 || options.columns > 4096 || options.rows > 4096) {
    throw InputError("--grid: expected CxR with 1 to 4096 columns and rows, got " +
                     std::to_string(options.columns) + "x" + std::to_string(options.rows));
  }
  PageBrowser browser(options.page);
  nlohmann::json facts;
  PageReconcileResult result = reconcileLoad(browser, options, false, facts);
  if (!options.toggle) {
    result.toggle.skipped = "--no-toggle";
    return result;
  }
  result.toggle.notApplicable = toggleRefusal(facts, result.reversedDepthBuffer);
  if (!result.toggle.notApplicable.empty()) return result;
  try {
    nlohmann::json toggledFacts;
    auto toggled =
        std::make_shared<PageReconcileResult>(reconcileLoad(browser, options, true, toggledFacts));
    result.toggle.failed =
        toggleFailure(toggledFacts, toggled->reversedDepthBuffer, !result.reversedDepthBuffer);
    if (result.toggle.failed.empty()) result.toggle.run = std::move(toggled);
  } catch (const InputError& error) {
    result.toggle.failed = error.what();
  }
  return result;
}

namespace {

// The fields of one run: its camera, depth state, picks, mismatches, state check and verdict.
nlohmann::json runJson(const PageReconcileResult& r) {
  const PageReconcileResult::Counts c = r.counts();
  nlohmann::json unexplained = nlohmann::json::array();
  for (const PagePick& pick : r.picks) {
    if (pick.kind == PagePick::Kind::Agree) continue;
    nlohmann::json entry = {{"x", pick.x},
                            {"y", pick.y},
                            {"class", kindName(pick.kind)},
                            {"edge_ambiguous", pick.ambiguous},
                            {"buffer_depth", pick.bufferDepth}};
    entry["ray_depth"] = pick.hit ? nlohmann::json(pick.rayDepth) : nlohmann::json(nullptr);
    entry["tolerance"] = pick.hit && std::isfinite(pick.tolerance) ? nlohmann::json(pick.tolerance)
                                                                   : nlohmann::json(nullptr);
    entry["object"] = pick.hit ? nlohmann::json(pick.object) : nlohmann::json(nullptr);
    unexplained.push_back(std::move(entry));
  }
  nlohmann::json check = pageCheckJson(r.check);
  check.erase("tool");
  return {
      {"camera", r.camera},
      {"depth",
       {{"reversed_depth_buffer", r.reversedDepthBuffer},
        {"clip_depth", r.clipDepth},
        {"clear_depth", r.clearDepth},
        {"depth_range", {r.depthRangeNear, r.depthRangeFar}},
        {"format", r.depthFormat},
        {"subpixel_bits", r.subpixelBits}}},
      {"picks",
       {{"total", r.picks.size()},
        {"agree", {{"surface", c.agreeSurface}, {"background", c.agreeBackground}}},
        {"depth_beyond_tolerance",
         {{"edge_ambiguous", c.depthEdge}, {"unexplained", c.depthUnexplained}}},
        {"ray_only", {{"edge_ambiguous", c.rayOnlyEdge}, {"unexplained", c.rayOnlyUnexplained}}},
        {"raster_only",
         {{"edge_ambiguous", c.rasterOnlyEdge}, {"unexplained", c.rasterOnlyUnexplained}}},
        {"max_depth_error", r.maxDepthError()},
        {"max_error_over_tolerance", r.maxErrorOverTolerance()}}},
      {"mismatches", unexplained},
      {"state_check", check},
      {"verdict", r.consistent() ? "consistent" : "inconsistent"}};
}

std::string onOff(bool on) {
  return on ? "on" : "off";
}

// The lines of one run under the page's line: depth state, state check, picks, the first
// unexplained mismatches.
void runText(std::ostream& out, const PageReconcileResult& r) {
  const PageReconcileResult::Counts c = r.counts();
  out << "  depth: clip " << r.clipDepth << ", reversedDepthBuffer " << onOff(r.reversedDepthBuffer)
      << ", cleared to " << number(r.clearDepth) << ", depthRange " << number(r.depthRangeNear)
      << ", " << number(r.depthRangeFar) << ", " << r.depthFormat << "\n";
  out << "  state check (clipray check --page): " << stateCheckCounts(r.check) << "\n";
  out << "  picks: the page's Raycaster.setFromCamera at " << r.columns << "x" << r.rows
      << " pixel centres, first hit against the depth buffer\n";
  out << (r.consistent() ? "consistent" : "inconsistent") << " agree " << c.agreeSurface << "+"
      << c.agreeBackground << " >tol " << (c.depthEdge + c.depthUnexplained) << " (e" << c.depthEdge
      << " u" << c.depthUnexplained << ") ray-only " << (c.rayOnlyEdge + c.rayOnlyUnexplained)
      << " (e" << c.rayOnlyEdge << " u" << c.rayOnlyUnexplained << ") raster-only "
      << (c.rasterOnlyEdge + c.rasterOnlyUnexplained) << " (e" << c.rasterOnlyEdge << " u"
      << c.rasterOnlyUnexplained << ") max |dz| " << number(r.maxDepthError()) << " ("
      << number(r.maxErrorOverTolerance()) << " tol)\n";
  out << "  agree: surface+background; >tol: depth beyond tolerance; ray-only: the ray hits, the "
         "pixel kept the clear depth; raster-only: the reverse; e edge-ambiguous, u unexplained\n";
  int shown = 0;
  for (const PagePick& pick : r.picks) {
    if (pick.kind == PagePick::Kind::Agree || pick.ambiguous) continue;
    if (shown++ == 5) break;
    out << "  pixel " << pick.x << "," << pick.y << ": " << kindName(pick.kind) << ", buffer "
        << number(pick.bufferDepth);
    if (pick.hit) {
      out << ", ray " << number(pick.rayDepth) << " (" << pick.object << ", tolerance "
          << number(pick.tolerance) << ")";
    }
    out << "\n";
  }
}

}  // namespace

nlohmann::json pageReconcileJson(const PageReconcileResult& r) {
  nlohmann::json report = {{"tool", "clipray reconcile --page"},
                           {"page", r.check.page},
                           {"url", r.check.url},
                           {"three_revision", r.revision},
                           {"canvas", r.canvas},
                           {"drawing_buffer", {r.width, r.height}},
                           {"css_size", {r.cssWidth, r.cssHeight}},
                           {"device_pixel_ratio", r.devicePixelRatio},
                           {"grid", {r.columns, r.rows}}};
  report.update(runJson(r));
  nlohmann::json toggled = {{"made", r.toggle.run != nullptr},
                            {"reversed_depth_buffer", !r.reversedDepthBuffer}};
  if (r.toggle.run) {
    toggled.update(runJson(*r.toggle.run));
  } else if (!r.toggle.skipped.empty()) {
    toggled["skipped"] = r.toggle.skipped;
    toggled["verdict"] = nullptr;
  } else if (!r.toggle.notApplicable.empty()) {
    toggled["not_applicable"] = r.toggle.notApplicable;
    toggled["verdict"] = nullptr;
  } else {
    toggled["failed"] = r.toggle.failed;
    toggled["verdict"] = "failed";
  }
  report["toggled"] = std::move(toggled);
  report["overall"] = r.allConsistent() ? "consistent" : "inconsistent";
  return report;
}

std::string pageReconcileText(const PageReconcileResult& r) {
  std::ostringstream out;
  out << "page " << r.check.page << ": three.js r" << r.revision << ", " << r.canvas << " "
      << r.width << "x" << r.height << " (devicePixelRatio " << number(r.devicePixelRatio) << "), "
      << r.camera.value("type", std::string("camera")) << "\n";
  runText(out, r);
  const std::string toggle = "toggled: reversedDepthBuffer " + onOff(!r.reversedDepthBuffer);
  if (r.toggle.run) {
    out << toggle << " (the page: " << onOff(r.reversedDepthBuffer)
        << "), the page loaded again with its renderer's depth buffer flipped before its first "
           "frame\n";
    runText(out, *r.toggle.run);
  } else if (!r.toggle.skipped.empty()) {
    out << toggle << ": not made (" << r.toggle.skipped << ")\n";
  } else if (!r.toggle.notApplicable.empty()) {
    out << toggle << ": not applicable: " << r.toggle.notApplicable << "\n";
  } else {
    out << toggle << ": failed: " << r.toggle.failed << "\n";
  }
  if (r.toggle.run || !r.toggle.failed.empty()) {
    out << "overall: " << (r.allConsistent() ? "consistent" : "inconsistent")
        << " (the page as it is and toggled)\n";
  }
  return out.str();
}

}  // namespace clipray::page
