#pragma once
// A pass drawn in every depth format (16 and 24 bits, 32-bit float), world and pretransformed
// vertices in turn run by run, for tests that compare what two analytic passes make of the same
// raster: body(format, compare), where compare(pass) is compareRasterFrame of that raster with
// the pass given (on two threads).

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/gl/Renderer.hpp"

namespace clipray::testing {

template <class Body>
void drawInEveryDepthFormat(gl::Renderer& renderer, const engine::AnalyticPass& drawn, int& runs,
                            Body&& body) {
  for (const DepthFormat format :
       {DepthFormat::Unorm16, DepthFormat::Unorm24, DepthFormat::Float32}) {
    const VertexMode vertexMode = runs % 2 == 0 ? VertexMode::World : VertexMode::Pretransformed;
    gl::RenderTimings timings;
    const RasterFrame raster =
        renderer.render(engine::renderRequest(drawn, format, vertexMode), &timings);
    const int subpixelBits = renderer.info().subpixelBits;
    const auto compare = [&](const engine::AnalyticPass& pass) {
      return engine::compareRasterFrame(pass, raster, format, vertexMode, subpixelBits, timings, 2);
    };
    body(format, compare);
    ++runs;
  }
}

}  // namespace clipray::testing
