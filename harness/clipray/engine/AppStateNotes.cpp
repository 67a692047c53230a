#include "clipray/engine/AppStateNotes.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/trace/GlTraceState.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray::engine {

namespace {

std::string clipControlText(ClipOrigin origin, DepthConvention convention) {
  return std::string(origin == ClipOrigin::UpperLeft ? "GL_UPPER_LEFT" : "GL_LOWER_LEFT") + ", " +
         (convention == DepthConvention::ZeroToOne ? "GL_ZERO_TO_ONE" : "GL_NEGATIVE_ONE_TO_ONE");
}

std::string cullingText(CullFace cull, FrontFace frontFace) {
  if (cull == CullFace::None) return "no face culling";
  return std::string("glCullFace(") + (cull == CullFace::Back ? "GL_BACK" : "GL_FRONT") +
         ") with glFrontFace(" + (frontFace == FrontFace::Ccw ? "GL_CCW" : "GL_CW") + ")";
}

bool sameCulling(CullFace cullA, FrontFace frontA, CullFace cullB, FrontFace frontB) {
  return cullA == cullB && (cullA == CullFace::None || frontA == frontB);
}

// Draw numbers (from 1) as "draw 3" or "draws 1, 2".
std::string drawList(const std::vector<std::size_t>& draws) {
  std::string text = draws.size() == 1 ? "draw " : "draws ";
  for (std::size_t k = 0; k < draws.size(); ++k) {
    text += (k ? ", " : "") + std::to_string(draws[k] + 1);
  }
  return text;
}

// "GL_POLYGON_OFFSET_FILL disabled" or "glPolygonOffsetClamp(factor, units, clamp)".
std::string offsetText(const std::optional<PolygonOffset>& offset) {
  if (!offset) return "GL_POLYGON_OFFSET_FILL disabled";
  return "glPolygonOffsetClamp(" + sixDigits(offset->factor) + ", " + sixDigits(offset->units) +
         ", " + sixDigits(offset->clamp) + ")";
}

}  // namespace

std::vector<std::string> appStateNotes(const std::vector<gl::AppDrawState>& draws, DepthMode mode,
                                       const Scene& scene, AppIds ids) {
  // Each difference once, with the draws it concerns, in the order first seen.
  std::vector<std::pair<std::string, std::vector<std::size_t>>> notes;
  const auto note = [&](std::size_t draw, std::string text) {
    for (auto& [known, drawsOfIt] : notes) {
      if (known == text) {
        drawsOfIt.push_back(draw);
        return;
      }
    }
    notes.push_back({std::move(text), {draw}});
  };
  const bool drawPerMesh = ids == AppIds::PerDrawCall || draws.size() == scene.objects.size();
  std::optional<std::size_t> sharedCulling;  // a mesh whose culling every mesh has
  if (!scene.objects.empty()) {
    sharedCulling = 0;
    for (const MeshObject& object : scene.objects) {
      const MeshObject& first = scene.objects[0];
      if (!sameCulling(object.cull, object.frontFace, first.cull, first.frontFace)) {
        sharedCulling.reset();
      }
    }
  }
  const bool greater = nearerIsGreater(mode, scene.depthRange);
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const gl::AppDrawState& d = draws[k];
    if (d.origin != mode.origin || d.convention != mode.convention) {
      note(k, "glClipControl(" + clipControlText(d.origin, d.convention) + "), but the run is " +
                  mode.name() + " (" + clipControlText(mode.origin, mode.convention) + ")");
    }
    // glDepthRange is stored in float by some implementations: equal within float rounding. A
    // draw of a mesh with a range of its own is held to that one.
    const MeshObject* drawnMesh =
        drawPerMesh && k < scene.objects.size() ? &scene.objects[k] : nullptr;
    const bool ownRange = drawnMesh && drawnMesh->depthRange.has_value();
    const glm::dvec2 declared = ownRange ? *drawnMesh->depthRange : scene.depthRange;
    if (std::abs(d.depthRange.x - declared.x) > 1e-6 ||
        std::abs(d.depthRange.y - declared.y) > 1e-6) {
      note(k, "glDepthRange(" + sixDigits(d.depthRange.x) + ", " + sixDigits(d.depthRange.y) +
                  "), but " +
                  (ownRange ? "the scene declares mesh \"" + drawnMesh->name + "\"'s "
                            : std::string("the scene declares ")) +
                  "(" + sixDigits(declared.x) + ", " + sixDigits(declared.y) + ") " +
                  (ownRange ? "(the object's depthRange, SceneBuilder::objectDepthRange)"
                            : "(depthRange, SceneBuilder::depthRange)"));
    }
    if (!d.depthTest) {
      note(k, std::string("the depth test is off; the run expects ") +
                  (greater ? "GL_GREATER" : "GL_LESS") + " (the nearer surface has the " +
                  (greater ? "greater" : "smaller") + " depth)");
    } else if (greater ? d.depthFunc != trace::kGlGreater && d.depthFunc != trace::kGlGequal
                       : d.depthFunc != trace::kGlLess && d.depthFunc != trace::kGlLequal) {
      note(k, "glDepthFunc(" + trace::glEnumName(d.depthFunc) + "), but under " + mode.name() +
                  (scene.depthRange.x > scene.depthRange.y ? " with a reversed depth range" : "") +
                  " the nearer surface has the " + (greater ? "greater" : "smaller") +
                  " depth: " + (greater ? "GL_GREATER" : "GL_LESS"));
    }
    if (d.cullsEverything) {
      note(k, "glCullFace(GL_FRONT_AND_BACK) with culling enabled: the draw shows nothing");
    }
    const std::optional<std::size_t> mesh =
        drawPerMesh && k < scene.objects.size() ? std::optional<std::size_t>(k) : sharedCulling;
    if (mesh && !d.cullsEverything) {
      const MeshObject& object = scene.objects[*mesh];
      if (!sameCulling(d.cull, d.frontFace, object.cull, object.frontFace)) {
        note(k, cullingText(d.cull, d.frontFace) + ", but the scene declares " +
                    cullingText(object.cull, object.frontFace) + " for mesh \"" + object.name +
                    "\" (cull and frontFace, SceneBuilder::faceCulling)");
      }
    }
    // The polygon offset the draw's mesh declares (none where no draw is known to be one mesh's
    // and no mesh declares one); GL stores factor, units and clamp in float.
    const bool anyOffset = std::any_of(scene.objects.begin(), scene.objects.end(),
                                       [](const MeshObject& o) { return o.polygonOffset; });
    if (drawnMesh || !anyOffset) {
      const std::optional<PolygonOffset> want =
          drawnMesh ? drawnMesh->polygonOffset : std::optional<PolygonOffset>();
      const auto close = [](double a, double b) {
        return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b));
      };
      const bool same = want.has_value() == d.polygonOffset.has_value() &&
                        (!want || (close(d.polygonOffset->factor, want->factor) &&
                                   close(d.polygonOffset->units, want->units) &&
                                   close(d.polygonOffset->clamp, want->clamp)));
      if (!same) {
        note(k, offsetText(d.polygonOffset) + ", but the scene declares " +
                    (want ? offsetText(want) : std::string("no polygon offset")) +
                    (drawnMesh ? " for mesh \"" + drawnMesh->name + "\"" : std::string()) +
                    " (polygonOffset, SceneBuilder::objectPolygonOffset)");
      }
    }
    if (d.depthClamp != scene.depthClamp) {
      note(k, d.depthClamp
                  ? "GL_DEPTH_CLAMP is enabled, but the scene does not declare it (depthClamp, "
                    "SceneBuilder::depthClamp): what the picture shows in front of the near plane "
                    "no ray from the near plane can hit"
                  : "GL_DEPTH_CLAMP is disabled, but the scene declares it (depthClamp, "
                    "SceneBuilder::depthClamp): the picture is clipped at the near and far planes");
    }
  }
  std::vector<std::string> lines;
  for (const auto& [text, drawsOfIt] : notes) lines.push_back(drawList(drawsOfIt) + ": " + text);
  return lines;
}

}  // namespace clipray::engine
