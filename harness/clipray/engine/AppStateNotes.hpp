#pragma once
// What the app's render function drew with, set beside what the run says it draws under: the
// clip control of the run's convention, the scene's depth range and each mesh's face culling, a
// depth test that keeps the nearer surface, no depth clamp. A difference is a note on the run, in
// words a graphics programmer can act on ("draw 1: glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE),
// but the run is zo-upper-left ..."): the pixels still decide whether the run is consistent (a
// state the pictures do not show, such as culling the back faces of closed meshes, is no failure),
// but where they disagree the note says why.

#include <string>
#include <vector>

#include "clipray/Reconcile.hpp"
#include "clipray/gl/AppRender.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// One line per difference, naming the draw calls it concerns (numbered from 1, in call order);
// empty when every draw agrees with the run. Draw k is taken to draw mesh k with one id per draw
// call, or when there are as many draws as meshes; otherwise a draw's culling is set beside the
// scene's only when every mesh declares the same.
std::vector<std::string> appStateNotes(const std::vector<gl::AppDrawState>& draws, DepthMode mode,
                                       const Scene& scene, AppIds ids);

}  // namespace clipray::engine
