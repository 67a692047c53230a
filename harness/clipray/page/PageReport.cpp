// `clipray check --page` reports: per canvas, the trace checker's report of its calls
// (TraceReport.cpp), under a line that says what the page and the canvas are.

#include <sstream>

#include "clipray/check/CheckText.hpp"
#include "clipray/page/PageCheck.hpp"

namespace clipray::page {

namespace {

std::string canvasLine(const CanvasCheck& canvas, double devicePixelRatio) {
  std::ostringstream out;
  const nlohmann::json& c = canvas.canvas;
  out << canvas.name << " (" << canvas.type << "): drawing buffer "
      << c.value("drawingBufferWidth", 0) << "x" << c.value("drawingBufferHeight", 0) << ", canvas "
      << c.value("canvasWidth", 0) << "x" << c.value("canvasHeight", 0) << ", shown at "
      << c.value("clientWidth", 0) << "x" << c.value("clientHeight", 0)
      << " CSS px, devicePixelRatio " << devicePixelRatio << ", depth buffer "
      << (c.value("depth", false) ? std::to_string(c.value("depthBits", 0)) + " bits" : "none")
      << (c.value("preserveDrawingBuffer", false) ? ", preserveDrawingBuffer" : "") << "; "
      << canvas.calls << " calls recorded, " << canvas.draws << " draws";
  return out.str();
}

}  // namespace

nlohmann::json pageCheckJson(const PageCheckResult& r) {
  nlohmann::json canvases = nlohmann::json::array();
  for (const CanvasCheck& canvas : r.canvases) {
    nlohmann::json entry = {{"name", canvas.name},
                            {"type", canvas.type},
                            {"canvas", canvas.canvas},
                            {"calls", canvas.calls},
                            {"draws", canvas.draws},
                            {"draws_without_depth_writes", canvas.drawsWithoutDepthWrites},
                            {"draws_with_polygon_offset", canvas.drawsWithPolygonOffset}};
    entry["polygon_offset"] = nullptr;
    if (canvas.drawsWithPolygonOffset > 0) {
      entry["polygon_offset"] = {{"factor", canvas.polygonOffsetFactor},
                                 {"units", canvas.polygonOffsetUnits}};
    }
    if (canvas.result) {
      nlohmann::json check = trace::traceCheckJson(*canvas.result);
      check.erase("tool");
      check.erase("trace");
      entry["check"] = std::move(check);
    } else {
      entry["not_checked"] = canvas.notChecked;
    }
    canvases.push_back(std::move(entry));
  }
  return {{"tool", "clipray check --page"},
          {"page", r.page},
          {"url", r.url},
          {"device_pixel_ratio", r.devicePixelRatio},
          {"frames", r.frames},
          {"draws", r.draws},
          {"calls_not_kept", r.callsNotKept},
          {"recorder_errors", r.recorderErrors},
          {"page_errors", r.pageErrors},
          {"canvases", canvases},
          {"verdict", r.hasErrors() ? "errors" : "ok"}};
}

std::string pageCheckText(const PageCheckResult& r) {
  std::ostringstream out;
  out << "page " << r.page << ": " << r.frames << " frames, " << r.draws << " draws on "
      << r.canvases.size() << (r.canvases.size() == 1 ? " canvas" : " canvases") << "\n";
  if (r.callsNotKept > 0) {
    out << "  " << r.callsNotKept << " calls past the recorder's limit not recorded\n";
  }
  for (const std::string& error : r.recorderErrors) out << "  recorder: " << error << "\n";
  for (const std::string& error : r.pageErrors) out << "  the page threw: " << error << "\n";
  for (const CanvasCheck& canvas : r.canvases) {
    out << "\n" << canvasLine(canvas, r.devicePixelRatio) << "\n";
    if (canvas.drawsWithoutDepthWrites > 0) {
      out << "  " << canvas.drawsWithoutDepthWrites
          << " draws with depthMask(false): they leave no depth to pick against\n";
    }
    if (canvas.drawsWithPolygonOffset > 0) {
      out << "  " << canvas.drawsWithPolygonOffset
          << " draws with POLYGON_OFFSET_FILL (last polygonOffset factor "
          << detail::checkNumber(canvas.polygonOffsetFactor) << ", units "
          << detail::checkNumber(canvas.polygonOffsetUnits)
          << "): the depth they write is shifted from the surface's\n";
    }
    if (!canvas.result) {
      out << "  not checked: " << canvas.notChecked << "\n";
      continue;
    }
    // The trace report without its first line (which names a trace): the canvas line above says
    // what was read.
    std::string text = trace::traceCheckText(*canvas.result);
    // --verify's observations come from the page's own depth buffer, not a replay.
    const std::string replayed = "  verify (replayed by eglretrace):\n";
    for (std::size_t at = text.find(replayed); at != std::string::npos;
         at = text.find(replayed, at + 1)) {
      text.replace(at, replayed.size(),
                   "  verify (the page's depth buffer after the last frame):\n");
    }
    const std::size_t colon = text.find(": ");
    out << "  calls read as a trace: " << text.substr(colon == std::string::npos ? 0 : colon + 2);
  }
  return out.str();
}

}  // namespace clipray::page
