#pragma once
// The ray side of a run from the app's own picking with its hits (PickHitFunction): the app's ray
// and hit at every pixel stand in for clipray's rays and intersection, so that what the app's
// intersection code finds (its culling policy included) is compared with the picture.

#include "clipray/Picking.hpp"

namespace clipray::engine {

struct AnalyticPass;

// Fills pass.frame (rays and hits, one per pixel of pass.drawnCamera's viewport; the app is asked
// with the drawn camera) and pass.pickNotes; pass.scene and pass.intersector must be set. A hit's
// mesh and triangle become the primitive id the raster writes for them; without a triangle, the
// mesh's triangle the ray meets nearest to the hit's t. Throws InputError, naming the pixel, for a
// hit on a mesh or triangle the scene lacks or at a t that is not finite and positive, and
// rethrows what the app's function throws.
void takeAppPickHits(AnalyticPass& pass, const PickHitFunction& pick, unsigned threadCount);

}  // namespace clipray::engine
