#pragma once
// Chooses the analytic path (AnalyticChoice.hpp) for a scope, and the default again after it,
// whatever happens inside: for tests that read what only one path gives (the ray path's t at every
// hit, or the screen path's planes).

#include "clipray/util/AnalyticChoice.hpp"

namespace clipray::testing {

class AnalyticPathFor {
 public:
  explicit AnalyticPathFor(AnalyticPath path) : previous_(chosenAnalyticPath()) {
    chooseAnalyticPath(path);
  }
  ~AnalyticPathFor() { chooseAnalyticPath(previous_); }
  AnalyticPathFor(const AnalyticPathFor&) = delete;
  AnalyticPathFor& operator=(const AnalyticPathFor&) = delete;

 private:
  AnalyticPath previous_;
};

}  // namespace clipray::testing
