#pragma once
// The named hard cases every ray method is measured on (docs/bench.md): cameras that break the
// usual methods. Each case carries its matrices and the inputs each method's source takes (separate
// projection and view, fov scalars where the camera is a symmetric perspective), its viewport and
// the convention it is drawn under. Most cases come in two variants, built for and drawn under
// NegativeOneToOne ("no") and ZeroToOne ("zo").

#include <optional>
#include <string>
#include <vector>

#include "clipray/Conventions.hpp"
#include "clipray/rays/RayMethods.hpp"

namespace clipray {

struct HardCase {
  std::string name;         // "standard", "eye_1e7", ... (shared by the no/zo variants)
  std::string description;  // one line: what it tests
  CameraInputs inputs;      // inputs.mode: the convention the matrix is drawn under
  Viewport viewport;
  std::optional<double> fovYDegrees;  // perspective cameras; nullopt for orthographic
  std::string convention() const { return inputs.mode.name(); }
};

// Every case at `size` (the bench's --size): cases with their own shape derive it from there
// (aspect_32_9: width x width * 9 / 32), except viewport_7x3, which is 7x3 whatever the size.
std::vector<HardCase> hardCases(Viewport size);
// The distinct case names, in order.
std::vector<std::string> hardCaseNames();

}  // namespace clipray
