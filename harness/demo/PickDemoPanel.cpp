// The demo's Dear ImGui panel: the scene and settings, the last pick's three answers and their gap,
// the key help, and the markers drawn over the picked pixel.

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "PickDemo.hpp"

namespace clipray::demo {

namespace {

std::string formatPoint(const std::optional<glm::dvec3>& p) {
  if (!p) return "-";
  char text[128];
  std::snprintf(text, sizeof text, "(%.6f, %.6f, %.6f)", p->x, p->y, p->z);
  return text;
}

std::string objectName(const Scene& scene, int object) {
  return surfaceName(scene, object);
}

ImVec4 verdictColour(PickVerdict verdict) {
  switch (verdict) {
    case PickVerdict::Agree:
      return {0.4f, 1.0f, 0.4f, 1.0f};
    case PickVerdict::Apart:
      return {1.0f, 0.65f, 0.2f, 1.0f};
    case PickVerdict::Ambiguous:
      return {1.0f, 0.9f, 0.3f, 1.0f};
    case PickVerdict::Disagree:
      return {1.0f, 0.35f, 0.35f, 1.0f};
    case PickVerdict::NoRay:
      break;
  }
  return {0.7f, 0.7f, 0.7f, 1.0f};
}

}  // namespace

void PickDemo::drawPanel() {
  const WindowGeometry geometry = window_->geometry();
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.82f);
  // Collapsible by its title bar's arrow; P shrinks it to the verdict line.
  ImGui::Begin("clipray-pick (P: compact, H: keys)", nullptr,
               ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
  if (!compactPanel_) {
    ImGui::Text("scene %s   %s", baseScene_.name.c_str(),
                teleported_ ? "TELEPORTED 1e5 from the origin" : "at the origin");
    ImGui::Text("convention %s   depth %s   vertices %s", settings_.mode.name().c_str(),
                depthFormatName(settings_.depthFormat).c_str(),
                vertexModeName(settings_.vertexMode).c_str());
    if (!camera_.clipPlanes.empty()) {
      // The picture is cut by them; so is every pick's ray, or it would find what is not shown.
      ImGui::Text("clip planes %zu (gl_ClipDistance): the rays are cut by them too",
                  camera_.clipPlanes.size());
    }
    ImGui::Text("rays %s   framebuffer %dx%d", rayChoiceName(settings_.ray).c_str(),
                geometry.framebufferSize.x, geometry.framebufferSize.y);
    ImGui::Separator();
  }
  if (!lastPick_) {
    ImGui::TextUnformatted("left-click to pick");
  } else {
    const PickResult& p = *lastPick_;
    const PickJudgement judgement = judgePick(p, shownScene_);
    if (!compactPanel_) {
      // The framebuffer pixel, as GL numbers it under either clip origin; the script's and the
      // cursor's coordinates are the window's (top-left origin, y down), so a click at y = 300
      // picks row 339 of 640.
      ImGui::Text("pixel (%d, %d)   %s", p.pixel.x, p.pixel.y,
                  pixelCoordinatesLabel(p.mode.origin));
      if (p.rayUnavailable.empty()) {
        ImGui::TextColored(ImVec4(0.4f, 1.0f, 0.4f, 1.0f), "1 ray   %-12s %s",
                           objectName(shownScene_, p.rayObject).c_str(),
                           formatPoint(p.rayPoint).c_str());
      } else {
        ImGui::TextColored(ImVec4(0.4f, 1.0f, 0.4f, 1.0f), "1 ray   %-12s %s", "n/a",
                           p.rayUnavailable.c_str());
      }
      ImGui::TextColored(ImVec4(1.0f, 0.65f, 0.2f, 1.0f), "2 depth %-12s %s", "",
                         formatPoint(p.depthPoint).c_str());
      ImGui::TextColored(ImVec4(0.4f, 0.9f, 1.0f, 1.0f), "3 id    %s",
                         objectName(shownScene_, p.idObject).c_str());
      if (p.gapWorld) {
        // Beyond a pixel, the depth readback's point is not the one the ray found.
        const bool far = p.gapPixels.value_or(0.0) > 1.0;
        ImGui::TextColored(far ? ImVec4(1.0f, 0.65f, 0.2f, 1.0f) : ImVec4(1, 1, 1, 1),
                           "gap 1-2: %.3g world units, %.3g px", *p.gapWorld,
                           p.gapPixels.value_or(0.0));
      } else {
        ImGui::TextUnformatted("gap 1-2: -");
      }
      if (p.reconcileClass) {
        ImGui::Text("reconcile's class here: %s", pixelClassName(*p.reconcileClass));
      }
    }
    ImGui::TextColored(verdictColour(judgement.verdict), "%s", judgement.text.c_str());
  }
  ImGui::End();

  if (showHelp_) {
    ImGui::SetNextWindowPos(ImVec2(8, static_cast<float>(geometry.windowSize.y) - 8),
                            ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.7f);
    ImGui::Begin("keys", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
    ImGui::TextUnformatted(
        "left-click pick   left-drag orbit   right-drag pan   wheel zoom\n"
        "C convention (no / zo / zo-reversed)   O clip origin (lower-left / upper-left)\n"
        "D depth format (16 / 24 / 32f)   V vertex mode (world / camera-relative / "
        "pretransformed)\n"
        "M ray method: unproject_glm / two_point / inverse_pv / fov_tangent / plane_cross /\n"
        "  plane_cross_pre / full / robust (float), then robust double\n"
        "T teleport 1e5   R reset view   P compact panel   H this help   Esc quit");
    ImGui::End();
  }

  // Markers: 1 where the ray hit, 2 where the depth readback unprojects to, 3 the picked pixel.
  if (lastPick_) {
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    const Viewport viewport = raster_.viewport;
    auto toScreen = [&](const glm::dvec2& framebuffer) {
      const glm::dvec2 w = geometry.cursorFromFramebuffer(framebuffer);
      return ImVec2(static_cast<float>(w.x), static_cast<float>(w.y));
    };
    const glm::dvec2 centre = glm::dvec2(lastPick_->pixel) + 0.5;
    const ImVec2 c = toScreen(centre);
    const float half = std::max(5.0f, static_cast<float>(0.5 / geometry.scale().x));
    draw->AddRect(ImVec2(c.x - half, c.y - half), ImVec2(c.x + half, c.y + half),
                  IM_COL32(100, 230, 255, 255), 0.0f, 0, 1.5f);
    if (lastPick_->rayPoint) {
      if (auto f =
              framebufferFromWorld(rasterCamera_.clipFromWorld, viewport, *lastPick_->rayPoint)) {
        draw->AddCircle(toScreen(*f), 9.0f, IM_COL32(100, 255, 100, 255), 20, 2.0f);
      }
    }
    if (lastPick_->depthPoint) {
      if (auto f =
              framebufferFromWorld(rasterCamera_.clipFromWorld, viewport, *lastPick_->depthPoint)) {
        const ImVec2 p = toScreen(*f);
        draw->AddLine(ImVec2(p.x - 7, p.y - 7), ImVec2(p.x + 7, p.y + 7),
                      IM_COL32(255, 165, 50, 255), 2.0f);
        draw->AddLine(ImVec2(p.x - 7, p.y + 7), ImVec2(p.x + 7, p.y - 7),
                      IM_COL32(255, 165, 50, 255), 2.0f);
      }
    }
  }
}

}  // namespace clipray::demo
