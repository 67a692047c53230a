#pragma once
// GoogleTest assertions for a project's own tests (header-only: clipray does not link GoogleTest).
//
//   EXPECT_PICKING_CONSISTENT(scene, pick, options);   // clipray::TestScene, PickRayFunction or
//                                                      // PickHitFunction,
//   ASSERT_PICKING_CONSISTENT(scene, pick, options);   // clipray::ReconcileOptions
//
// A failure prints every run's summary line, the worst pixels of each inconsistent run with what
// the raster and the ray hit there (and where, in the app's window coordinates when
// options.window is set), and the images' paths when options.reportDirectory is set.

#include <gtest/gtest.h>

#include "clipray/Reconcile.hpp"

namespace clipray::testing {

// Pick: a PickRayFunction or a PickHitFunction (or what converts to one).
template <class Pick>
::testing::AssertionResult pickingConsistent(const char* sceneExpression,
                                             const char* pickExpression,
                                             const char* /*optionsExpression*/,
                                             const TestScene& scene, const Pick& pick,
                                             const ReconcileOptions& options) {
  const ReconcileResult result = reconcile(scene, pick, options);
  if (result.consistent()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "the picking of " << pickExpression << " and the raster disagree on " << sceneExpression
         << " (scene \"" << scene.name() << "\"):\n"
         << result.text();
}

}  // namespace clipray::testing

#define EXPECT_PICKING_CONSISTENT(scene, pick, options) \
  EXPECT_PRED_FORMAT3(::clipray::testing::pickingConsistent, scene, pick, options)
#define ASSERT_PICKING_CONSISTENT(scene, pick, options) \
  ASSERT_PRED_FORMAT3(::clipray::testing::pickingConsistent, scene, pick, options)
