#pragma once
// Projection and view matrices of real engines, written by us from their public sources (issue
// #24), for the generated-camera tests of `clipray check`. One header per engine under
// support/engines/, each citing its repository and paths:
//
//   Common.hpp       Mat4 (column-major doubles, 4 * col + row, p_clip = M * p), multiply,
//                    transpose, roundToFloat32, vulkanYFlip, inverse
//   Glm.hpp          glmx::      g-truc/glm: perspective / perspectiveFov / infinitePerspective /
//                                frustum / ortho in RH / LH x NO / ZO, lookAtRH / LH
//   ThreeJs.hpp      threejs::   mrdoob/three.js: makePerspective / makeOrthographic (WebGL,
//                                WebGPU, reversedDepth), PerspectiveCamera, OrthographicCamera
//   Godot.hpp        godot::     godotengine/godot: Projection set_perspective / set_frustum /
//                                set_orthogonal, depth correction (reversed Z, 4.3+), look_at
//   Bgfx.hpp         bgfx::      bkaradzic/bx: mtxProj / mtxProjInf / mtxOrtho / mtxLookAt with
//                                homogeneousNdc and Handedness
//   Filament.hpp     filament::  google/filament: Camera projection (infinite far) and the
//                                reversed-Z matrix the shaders get, lookAt
//   DirectXMath.hpp  dxmath::    microsoft/DirectXMath: XMMatrixPerspectiveFov / Orthographic /
//                                LookAt LH / RH (row vectors) and their memory order
//   Raylib.hpp       raylib::    raysan5/raylib: MatrixPerspective / Frustum / Ortho / LookAt,
//                                GetCameraProjectionMatrix, BeginMode3D
//   Oblique.hpp      oblique::   Lengyel's oblique near plane (NO, ZO, reversed ZO)
//
// Every builder is a template on the scalar type the engine computes in; see Common.hpp.

#include "support/engines/Bgfx.hpp"
#include "support/engines/Common.hpp"
#include "support/engines/DirectXMath.hpp"
#include "support/engines/Filament.hpp"
#include "support/engines/Glm.hpp"
#include "support/engines/Godot.hpp"
#include "support/engines/Oblique.hpp"
#include "support/engines/Raylib.hpp"
#include "support/engines/ThreeJs.hpp"
