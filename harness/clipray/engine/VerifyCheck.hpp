#pragma once
// `clipray check --verify`: back a diagnosis with pixels. A probe scene is built inside the
// matrix's view volume and rasterized with the app's matrix under the app's declared conventions,
// then reconciled with clipray's rays; probes at chosen depths test the specific findings.

#include <nlohmann/json.hpp>

#include "clipray/check/ConventionCheck.hpp"
#include "clipray/gl/Renderer.hpp"

namespace clipray::engine {

struct VerifyResult {
  RunMetrics reconcile;  // probe scene: raster vs robust rays under the declared conventions
  // A probe at 1.5x the near plane the matrix was built for: drawn or clipped?
  std::optional<bool> nearProbeDrawn;
  double nearProbeDistance = 0.0;
  // Two overlapping probes at different depths: does the raster show the nearer one?
  bool nearerProbeWins = true;
  std::vector<std::string> observations;  // one sentence each, for the report
};

VerifyResult verifyCheck(const CheckInput& input, const CheckReport& report,
                         gl::Renderer& renderer);
nlohmann::json verifyResultJson(const VerifyResult& result);

}  // namespace clipray::engine
