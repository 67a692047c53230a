#!/usr/bin/env python3
"""Writes the shipped scenes (scenes/*.json). Deterministic: the same files every run.

Each scene's "comment" says what it tests. Run from anywhere: python3 scenes/generate.py
"""
import json
import math
import os
import re

HERE = os.path.dirname(os.path.abspath(__file__))


def quad(name, a, b, c, d):
    """Two triangles a-b-c, a-c-d."""
    return {"name": name, "type": "mesh", "positions": [*a, *b, *c, *d], "indices": [0, 1, 2, 0, 2, 3]}


def box(name, centre, size, rotate=None):
    sx, sy, sz = (s / 2 for s in size)
    corners = [(x, y, z) for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = []
    for a, b, c, d in faces:
        indices += [a, b, c, a, c, d]
    obj = {"name": name, "type": "mesh", "positions": [v for p in corners for v in p], "indices": indices,
           "transform": {"translate": list(centre)}}
    if rotate:
        obj["transform"]["rotateDegrees"] = {"axis": rotate[0], "angle": rotate[1]}
    return obj


def tetrahedron(name, centre, radius):
    s = radius / math.sqrt(3)
    verts = [(s, s, s), (s, -s, -s), (-s, s, -s), (-s, -s, s)]
    return {"name": name, "type": "mesh", "positions": [v for p in verts for v in p],
            "indices": [0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2], "transform": {"translate": list(centre)}}


def icosphere(name, centre, radius, level):
    t = (1 + math.sqrt(5)) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
             (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [tuple(c / math.sqrt(1 + t * t) for c in v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache = {}

        def middle(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                m = [(a + b) / 2 for a, b in zip(verts[i], verts[j])]
                n = math.sqrt(sum(c * c for c in m))
                verts.append(tuple(c / n for c in m))
                cache[key] = len(verts) - 1
            return cache[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    # Shared vertices are stored once, so shared edges are bit-identical in both triangles.
    positions = [round(c * radius, 12) for v in verts for c in v]
    return {"name": name, "type": "mesh", "positions": positions, "indices": [i for f in faces for i in f],
            "transform": {"translate": list(centre)}}


def perspective(name, eye, target, fov, near, far=None, viewport=(320, 240), up=(0, 1, 0), built_for=None,
                expected_findings=None):
    cam = {"name": name, "viewport": list(viewport),
           "view": {"eye": list(eye), "target": list(target), "up": list(up)},
           "projection": {"type": "perspective", "fovYDegrees": fov, "near": near}}
    if far is not None:
        cam["projection"]["far"] = far
    if built_for:
        cam["builtFor"] = built_for
    if expected_findings:
        # The clipray check findings the scene shows on purpose: each reconcile run notes them as
        # expected instead of failing with the verdict convention-error.
        cam["expectedFindings"] = expected_findings
    return cam


def write(name, comment, cameras, objects, conventions=None, depth_clamp=False, depth_range=None):
    scene = {"version": 1, "comment": comment}
    if conventions:
        scene["conventions"] = conventions
    if depth_range:
        scene["depthRange"] = list(depth_range)
    if depth_clamp:
        scene["depthClamp"] = True
    scene["cameras"] = cameras
    scene["objects"] = objects
    text = json.dumps(scene, indent=1)
    # Keep number arrays on one line each: readable files, small diffs.
    text = re.sub(r"\[\s*([-0-9.e+,\s]+?)\s*\]", lambda m: "[" + ", ".join(m.group(1).split()).replace(",,", ",") + "]",
                  text)
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        f.write(text + "\n")


# ---- Matrices in double, column vectors; m[r][c] (row-major lists), written column-major. ----

def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def mat_vec(m, v):
    return [sum(m[r][k] * v[k] for k in range(4)) for r in range(4)]


def mat_inverse(m):
    """Gauss-Jordan with partial pivoting."""
    a = [list(map(float, row)) + [1.0 if r == c else 0.0 for c in range(4)] for r, row in enumerate(m)]
    for col in range(4):
        pivot = max(range(col, 4), key=lambda r: abs(a[r][col]))
        a[col], a[pivot] = a[pivot], a[col]
        inv = 1.0 / a[col][col]
        a[col] = [x * inv for x in a[col]]
        for r in range(4):
            if r != col and a[r][col] != 0.0:
                f = a[r][col]
                a[r] = [x - f * y for x, y in zip(a[r], a[col])]
    return [row[4:] for row in a]


def transpose(m):
    return [[m[c][r] for c in range(4)] for r in range(4)]


def look_at_rh(eye, target, up):
    """glm::lookAtRH: view space looks down -z, y up."""
    def sub(a, b):
        return [x - y for x, y in zip(a, b)]

    def norm(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    def dot(a, b):
        return sum(x * y for x, y in zip(a, b))
    f = norm(sub(target, eye))
    s = norm(cross(f, up))
    u = cross(s, f)
    return [[s[0], s[1], s[2], -dot(s, eye)], [u[0], u[1], u[2], -dot(u, eye)],
            [-f[0], -f[1], -f[2], dot(f, eye)], [0.0, 0.0, 0.0, 1.0]]


def perspective_rh(fov_y_degrees, aspect, near, far, convention):
    """glm::perspectiveRH_NO ("no": z_ndc in [-1, 1]) or perspectiveRH_ZO ("zo": [0, 1])."""
    f = 1.0 / math.tan(math.radians(fov_y_degrees) / 2)
    if convention == "no":
        a, b = -(far + near) / (far - near), -2 * far * near / (far - near)
    else:
        a, b = -far / (far - near), -far * near / (far - near)
    return [[f / aspect, 0.0, 0.0, 0.0], [0.0, f, 0.0, 0.0], [0.0, 0.0, a, b], [0.0, 0.0, -1.0, 0.0]]


def lengyel_oblique(projection, view_plane, convention):
    """Eric Lengyel, "Oblique View Frustum Depth Projection and Clipping" (2005): the depth row of
    `projection` is replaced so that the near plane is the view-space plane C (eye on its negative
    side, C . p > 0 kept) and the far plane passes through the old far corner q = P^-1 (sgn C'x,
    sgn C'y, 1, 1), C' = P^-T C. NO (his OpenGL form): row 2 := (2 / C.q) C - row 3; ZO (his Direct3D
    form): row 2 := (1 / C.q) C. Points on C land on z_ndc = -1 (NO) or 0 (ZO)."""
    inv = mat_inverse(projection)
    clip_plane = mat_vec(transpose(inv), view_plane)
    sgn = [(x > 0) - (x < 0) for x in clip_plane]
    q = mat_vec(inv, [sgn[0], sgn[1], 1.0, 1.0])
    cq = sum(c * x for c, x in zip(view_plane, q))
    m = [list(row) for row in projection]
    if convention == "no":
        m[2] = [2.0 / cq * c - w for c, w in zip(view_plane, projection[3])]
    else:
        m[2] = [1.0 / cq * c for c in view_plane]
    return m


def column_major(m):
    return [m[r][c] for c in range(4) for r in range(4)]


def main():
    ground = quad("ground", (-4, 0, -4), (-4, 0, 4), (4, 0, 4), (4, 0, -4))
    write("standard",
          "A plain perspective camera (60 deg, near 0.1, far 100) on a ground quad, a box and a tetrahedron: "
          "the baseline every convention must reconcile.",
          [perspective("main", (3, 2.5, 5), (0, 0.5, 0), 60, 0.1, 100)],
          [ground, box("box", (0, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30)), tetrahedron("tetra", (1.8, 0.6, 0.8), 0.6)])

    # Seed 002's renderer case: near 0.01, eye about 280 units from the origin, in float.
    far_objects = [quad("ground", (-60, 0, -60), (-60, 0, 60), (60, 0, 60), (60, 0, -60)),
                   box("tower", (0, 10, 0), (8, 20, 8), ((0, 1, 0), 20)), box("crate", (15, 3, 10), (6, 6, 6)),
                   icosphere("ball", (-12, 5, 8), 5, 2)]
    write("far_from_origin",
          "Seed 002's renderer case: near plane 0.01, eye about 280 units from the origin, looking at geometry "
          "near the origin. Float matrices and positions lose precision here (world vertex mode).",
          [perspective("main", (200, 140, 130), (0, 5, 0), 40, 0.01, 1000)], far_objects)

    write("infinite_far",
          "Perspective with no far plane (t_max = +inf): the far-plane sign fix of seed 002 listing 4 fails here. "
          "A ground quad and a distant wall 1e5 units away.",
          [perspective("main", (0, 2, 6), (0, 1.5, 0), 50, 0.1, None, expected_findings=["infinite-far-plane"])],
          [quad("ground", (-1e3, 0, -1e5), (-1e3, 0, 10), (1e3, 0, 10), (1e3, 0, -1e5)),
           quad("far_wall", (-5e4, -10, -1e5), (5e4, -10, -1e5), (5e4, 3e4, -1e5), (-5e4, 3e4, -1e5)),
           box("box", (0, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30))])

    write("reversed_z",
          "Reversed-Z with an infinite far plane (near -> 1, far -> 0, depth test GREATER, clear 0), as modern "
          "engines draw. Only meaningful with glClipControl ZERO_TO_ONE, so it runs under zo-reversed only.",
          [perspective("main", (3, 2.5, 5), (0, 0.5, 0), 60, 0.05, None, expected_findings=["infinite-far-plane"])],
          [quad("ground", (-400, 0, -400), (-400, 0, 400), (400, 0, 400), (400, 0, -400)),
           box("box", (0, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30)), icosphere("ball", (-1.5, 0.7, -1), 0.7, 2),
           box("distant", (-40, 10, -300), (30, 20, 30))],
          conventions=["zo-reversed"])

    ortho_eye = (5000, 3000, 4000)
    write("ortho_far_from_origin",
          "Orthographic camera 7000 units from the origin looking at geometry near the origin: every ray has the "
          "same direction, so the ray origins carry the error.",
          [{"name": "main", "viewport": [320, 240],
            "view": {"eye": list(ortho_eye), "target": [0, 0, 0], "up": [0, 1, 0]},
            "projection": {"type": "orthographic", "left": -8, "right": 8, "bottom": -6, "top": 6,
                           "near": 6000, "far": 8000}}],
          [ground, box("box", (0, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30)), icosphere("ball", (-2, 1, 1.5), 1, 2)])

    write("near_plane_straddle",
          "Geometry straddling the near plane and reaching behind the camera: a long wall and floor pass through "
          "the eye's surroundings. Rays must start on the near plane the rasterizer clips at.",
          [perspective("main", (0, 1, 0), (0, 0.8, -5), 70, 0.5, 50)],
          [quad("floor", (-3, 0, 5), (3, 0, 5), (3, 0, -20), (-3, 0, -20)),
           quad("left_wall", (-0.3, -1, 5), (-0.3, -1, -20), (-0.3, 3, -20), (-0.3, 3, 5)),
           box("pillar", (0.4, 1, -0.3), (0.3, 3, 0.3)), box("crate", (0.5, 0.5, -4), (1, 1, 1))])

    write("coplanar",
          "Coplanar overlapping quads with different ids (z-fighting) beside a slightly raised quad: id mismatches "
          "on the coplanar pair are depth-ambiguous, the raised one must win everywhere it covers.",
          [perspective("main", (0, 3, 4), (0, 0, 0), 50, 0.1, 100)],
          [quad("under", (-2, 0, -2), (-2, 0, 2), (2, 0, 2), (2, 0, -2)),
           quad("over", (-1, 0, -1.5), (-1, 0, 2.5), (3, 0, 2.5), (3, 0, -1.5)),
           quad("raised", (-1.5, 0.05, -1), (-1.5, 0.05, 0), (-0.5, 0.05, 0), (-0.5, 0.05, -1))])

    write("grazing_floor",
          "A large floor seen at a grazing angle from 0.3 units up: depth changes fast per pixel near the "
          "horizon, so the depth-gradient part of the tolerance matters.",
          [perspective("main", (0, 0.3, 0), (0, 0.25, -10), 60, 0.05, 5000)],
          [quad("floor", (-500, 0, 10), (500, 0, 10), (500, 0, -5000), (-500, 0, -5000)),
           box("marker", (0, 0.5, -20), (1, 1, 1))])

    write("closed_mesh",
          "A closed icosphere (1280 triangles) filling the view: a ray slipping through a shared edge would hit "
          "the back side, which the id and depth comparison would show. Watertight intersection must not let any "
          "through.",
          [perspective("main", (0, 0, 3), (0, 0, 0), 45, 0.1, 100)],
          [icosphere("sphere", (0, 0, 0), 1, 3)])

    culled_box = box("box", (-1.2, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30))
    culled_box["cull"] = "back"
    mirrored_box = box("mirrored_box", (1.2, 0.5, 0), (1, 1, 1), ((0, 1, 0), 30))
    mirrored_box["transform"]["scale"] = [-1, 1, 1]
    mirrored_box["cull"] = "back"
    card = quad("card", (-0.8, 0.2, 1.6), (0.8, 0.2, 1.6), (0.8, 1.4, 1.6), (-0.8, 1.4, 1.6))
    card["indices"] = [0, 2, 1, 0, 3, 2]  # wound clockwise seen from the camera: its back
    card["cull"] = "back"
    write("face_culling",
          "Back-face culling (glCullFace(GL_BACK), glFrontFace(GL_CCW)) as GL decides it, by the winding on "
          "screen: a closed box shows its outside; its mirror image (scale -1 in x keeps the index order, so "
          "its faces wind clockwise) shows its inside; a card seen from behind is not drawn and the ground shows "
          "through it. Under zo-upper-left the projection clipray builds flips y, which reverses every winding "
          "on screen: the box shows its inside and the mirrored one its outside, as in a Direct3D-style app that "
          "keeps GL_CCW. The rays cull what the picture culls under both.",
          [perspective("main", (0.5, 2.5, 5), (0, 0.5, 0), 55, 0.1, 100,
                       expected_findings=["face-culling-keeps-insides"])],
          [ground, culled_box, mirrored_box, card], conventions=["zo", "zo-upper-left"])

    barrel = box("barrel", (0.25, 1.3, 3.2), (0.24, 0.24, 2.8))
    write("depth_clamp",
          "GL_DEPTH_CLAMP: nothing is clipped at the near plane (0.5 from the eye), so a long barrel held in "
          "front of the camera (a first-person weapon) is drawn whole, its part in front of the near plane at "
          "the near depth; a box beyond the far plane (40) is clipped all the same, since its clamped depth is "
          "the clear value the strict depth test never passes. The rays start at the eye and reach the barrel; "
          "its pixels in front of the near plane are a class of their own (in_front_of_near): a picking ray "
          "that starts on the near plane cannot hit them.",
          [perspective("main", (0, 1.5, 4), (0, 1, 0), 60, 0.5, 40)],
          [ground, box("crate", (-1, 0.5, -1), (1, 1, 1), ((0, 1, 0), 25)), barrel,
           box("beyond_far", (3, 2, -45), (4, 4, 4))],
          conventions=["no", "zo", "zo-reversed", "zo-upper-left"], depth_clamp=True)

    weapon = box("weapon", (0.25, 1.3, 3.1), (0.12, 0.12, 1.4))
    weapon["depthRange"] = [0, 0.1]
    write("object_depth_range",
          "A depth range per object: a first-person weapon drawn with glDepthRange(0, 0.1), the world with "
          "(0.1, 1). The player stands 0.6 in front of a wall that the weapon (0.2 to 1.6 from the eye) reaches "
          "through; the weapon shows whole, its far part in front of the nearer wall, because the depth test "
          "compares window depths and every weapon depth is below every world depth. The rays trace the weapon "
          "and the world apart and keep, per pixel, the hit with the smaller window depth.",
          [perspective("main", (0, 1.5, 4), (0, 1, 0), 60, 0.05, 100)],
          [ground, quad("wall", (-0.3, 0, 3.4), (2, 0, 3.4), (2, 3, 3.4), (-0.3, 3, 3.4)),
           box("crate", (-1, 0.5, -1), (1, 1, 1), ((0, 1, 0), 25)), weapon],
          conventions=["no", "zo", "zo-upper-left"], depth_range=(0.1, 1))

    house = box("house", (0, 0.8, 0), (2.4, 1.5, 1.6))  # its floor 0.05 above the ground: no tie
    house["clipPlanes"] = [[-1, 0, 0, 0.3]]  # keeps x <= 0.3: the part toward the camera cut away
    write("object_clip_planes",
          "A section view: a closed box (a house, say) cut by a clip plane of its own (clipPlanes [-1, 0, 0, "
          "0.3] on the object: gl_ClipDistance for its draw only) shows its inside through the cut, while the "
          "ground and a crate drawn without the plane stay whole. The rays of the house are cut by its plane, "
          "those of the rest by the camera's (none) alone.",
          [perspective("main", (3.5, 2.2, 3), (0, 0.5, 0), 50, 0.1, 100)],
          [ground, house, box("crate", (1.4, 0.35, 1.2), (0.7, 0.7, 0.7), ((0, 1, 0), 20))],
          conventions=["no", "zo", "zo-reversed", "zo-upper-left"])

    # Exactly coplanar in double: the wall and the decal both lie in z = -0.5 y.
    decal = quad("decal", (-0.8, 1, -0.5), (0.8, 1, -0.5), (0.8, 2, -1), (-0.8, 2, -1))
    decal["polygonOffset"] = {"factor": -1, "units": -2}
    write("polygon_offset",
          "Polygon offset: a decal coplanar with a slanted wall, drawn with glPolygonOffset(-1, -2): under "
          "GL_LESS a negative offset moves its depths toward the camera, so it shows over the wall at every "
          "pixel of its overlap instead of fighting it (a reversed-Z app flips both signs). The offset is "
          "m * factor + r * units (GL 4.6 14.6.5), m the wall's depth slope on screen and r the format's "
          "minimum resolvable difference; the compare accepts any depth in the interval the implementation's "
          "freedom allows and report.json shows the predicted interval beside the measured offsets.",
          [perspective("main", (0.7, 1.6, 4), (0, 1.2, -0.5), 50, 0.1, 100)],
          [ground, quad("wall", (-2, 0, 0), (2, 0, 0), (2, 3, -1.5), (-2, 3, -1.5)), decal],
          conventions=["no", "zo", "zo-upper-left"])

    # A large world seen through a logarithmic depth the mesh shader writes: a crate 6 m away, a tower at
    # 150 m, a block at 3 km and a ridge at 15 km over ground in distance bands (each band's far edge
    # at most ten times its near one). Every object is lifted off the ground (no coplanar faces).
    bands = [(3, -20, 12), (-20, -200, 120), (-200, -2000, 1200), (-2000, -19000, 12000)]
    log_ground = [quad("ground %d" % k, (-w, 0, z0), (w, 0, z0), (w, 0, z1), (-w, 0, z1))
                  for k, (z0, z1, w) in enumerate(bands)]
    log_objects = log_ground + [
        box("crate", (1, 0.55, -6), (1, 1, 1), ((0, 1, 0), 30)),
        box("tower", (-20, 16, -150), (10, 30, 10)),
        box("block", (300, 110, -3000), (400, 200, 400), ((0, 1, 0), 15)),
        tetrahedron("ridge", (-4000, 1800, -15000), 3000),
    ]
    three_cam = perspective("threejs", (0, 2, 0), (0, 1.5, -100), 60, 0.1, 20000)
    three_cam["logarithmicDepth"] = {"form": "threejs", "far": 20000}
    outerra_cam = perspective("outerra", (40, 30, 20), (0, 10, -300), 55, 0.5, 20000)
    outerra_cam["logarithmicDepth"] = {"form": "outerra", "far": 20000, "constant": 0.05}
    write("logarithmic_depth",
          "Logarithmic depth written by the mesh fragment shader (camera logarithmicDepth): three.js's "
          "logarithmicDepthBuffer (gl_FragDepth = log2(1 + w) / log2(1 + far)) and Outerra's with its constant "
          "C (log2(1 + C w) / log2(1 + C far)), 1 - that under reversed-Z, over a world from 6 m to 15 km "
          "(near 0.1, far 20000). The depth buffer holds a function of clip w, not the projective depth: "
          "the compare maps each exact hit's w the same way, and a depth-buffer picking function must "
          "invert that mapping, not unproject the depth through the inverse matrix.",
          [three_cam, outerra_cam], log_objects, conventions=["no", "zo", "zo-reversed"])

    write("no_matrix_under_zo",
          "A projection built for NO (z_n = -1, near 1, far 100) drawn under both conventions. Under ZO the "
          "rasterizer clips at z_ndc = 0, about 2 units away, so the effective near plane moves: the slanted quad "
          "between 1 and 3 units is cut further out, and the rays must start there too.",
          [perspective("main", (0, 0, 0), (0, 0, -1), 60, 1.0, 100, built_for="no",
                       expected_findings=["depth-convention-mismatch"])],
          [quad("slanted", (-0.6, -0.6, -1.2), (0.6, -0.6, -1.2), (0.6, 0.6, -3.0), (-0.6, 0.6, -3.0)),
           box("back", (0, 0, -6), (3, 3, 0.5))])

    # A planar water reflection: the main camera's view mirrored in the water plane y = 0 (det < 0, a
    # mirrored image, as a reflection pass renders it), with Lengyel's oblique near plane at the water
    # level so that nothing below the water reaches the reflection. The mirrored eye (0, -3, 12) looks
    # up 11.8 deg with a 60 deg fov: the water's horizon crosses the image, and every pixel below it
    # looks down, away from the water: its line of sight meets the near plane only behind the eye, so
    # it has no ray and the rasterizer must show nothing there. One camera per convention (a raw
    # clipFromWorld is drawn unchanged under both; under the other convention its near plane tilts to
    # another plane through the same horizon line, still a valid camera).
    main_eye, main_target = (0.0, 3.0, 12.0), (0.0, 0.5, 0.0)
    mirror = [[1.0, 0.0, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    reflected_view = mat_mul(look_at_rh(main_eye, main_target, (0.0, 1.0, 0.0)), mirror)
    # The water plane (0, 1, 0, 0) in the reflection camera's view space: C_view = V^-T C_world.
    water_in_view = mat_vec(transpose(mat_inverse(reflected_view)), [0.0, 1.0, 0.0, 0.0])
    reflection_cameras = []
    for convention in ("no", "zo"):
        projection = lengyel_oblique(perspective_rh(60, 320 / 240, 0.1, 1000, convention), water_in_view,
                                     convention)
        # The mirrored view reads as y-flipped. Its oblique near plane leaves NO and ZO readings
        # alike (clipray check: ambiguous), so drawing it under the other convention is no finding.
        reflection_cameras.append({"name": "reflection_" + convention, "viewport": [320, 240],
                                   "clipFromWorld": [float("%.17g" % x) for x in
                                                     column_major(mat_mul(projection, reflected_view))],
                                   "expectedFindings": ["y-flipped"]})
    write("water_reflection",
          "A water reflection: the view from (0, 3, 12) mirrored in the water plane y = 0, with Lengyel's oblique "
          "near plane at the water level (camera reflection_no built for NO, reflection_zo for ZO), the horizon "
          "in view. Pixels below the horizon look away from the water: no ray, and the raster must show nothing "
          "there. Above the water a tower, a crate and a ball; a post, a rock and an analytic sphere (the buoy, drawn "
          "by the primitive shader's own rays) crossing the water are cut at y = 0; a submerged box between the mirrored eye and the water and the sea floor are clipped entirely.",
          reflection_cameras,
          [box("tower", (-3, 4, -4), (2, 8, 2), ((0, 1, 0), 20)), box("crate", (2.5, 0.75, 2), (1.5, 1.5, 1.5)),
           icosphere("ball", (0.5, 2.2, -1), 1.2, 2), box("post", (-1, 0.5, 4), (0.4, 3, 0.4)),
           tetrahedron("rock", (3.5, 0.1, -2), 1.0),
           {"name": "buoy", "type": "sphere", "centre": [-2.2, 0.2, 6.5], "radius": 0.6},
           box("submerged", (0, -1.5, 8), (3, 1, 1)),
           quad("sea_floor", (-30, -5, 15), (30, -5, 15), (30, -5, -30), (-30, -5, -30))],
          conventions=["no", "zo"])

    # The same reflection clipped the other way: a plain projection (near 0.1) and a user clip plane
    # at the water (gl_ClipDistance = y, world space) instead of the oblique near plane. Meshes only:
    # the analytic primitives' shader does not apply clip planes.
    clipped_cameras = []
    for convention in ("no", "zo"):
        projection = perspective_rh(60, 320 / 240, 0.1, 1000, convention)
        clipped_cameras.append({"name": "clipped_" + convention, "viewport": [320, 240],
                                "clipFromWorld": [float("%.17g" % x) for x in
                                                  column_major(mat_mul(projection, reflected_view))],
                                "clipPlanes": [[0.0, 1.0, 0.0, 0.0]],
                                # Mirrored (y-flipped), and drawn under both conventions: the plain
                                # projection is a NO or ZO build the check tells apart.
                                "expectedFindings": ["depth-convention-mismatch", "y-flipped"]})
    write("water_reflection_clipped",
          "water_reflection's mirrored view clipped by a user clip plane at the water (clipPlanes [0, 1, 0, 0]: "
          "gl_ClipDistance = y, kept where y >= 0) instead of Lengyel's oblique near plane; the near plane stays at "
          "0.1 in front of the mirrored eye (camera clipped_no built for NO, clipped_zo for ZO). Geometry crossing "
          "the water is cut at y = 0 by the plane, the submerged box and the sea floor are clipped entirely, and "
          "every ray starts where its line of sight crosses the water.",
          clipped_cameras,
          [box("tower", (-3, 4, -4), (2, 8, 2), ((0, 1, 0), 20)), box("crate", (2.5, 0.75, 2), (1.5, 1.5, 1.5)),
           icosphere("ball", (0.5, 2.2, -1), 1.2, 2), box("post", (-1, 0.5, 4), (0.4, 3, 0.4)),
           tetrahedron("rock", (3.5, 0.1, -2), 1.0), box("submerged", (0, -1.5, 8), (3, 1, 1)),
           quad("sea_floor", (-30, -5, 15), (30, -5, 15), (30, -5, -30), (-30, -5, -30))],
          conventions=["no", "zo"])

    # ---- Analytic primitives (drawn exactly by a fragment shader on a proxy, see shaders/) ----
    write("primitives",
          "One of each analytic primitive: sphere, disk, quad, axis-aligned box, oriented box, and an infinite "
          "ground plane (full-screen proxy; the far plane at 200 cuts it at the horizon). Each is intersected in "
          "double on the CPU and in float in primitive.frag from the same clipFromWorld.",
          [perspective("main", (4, 3, 6), (0, 0.6, 0), 55, 0.1, 200)],
          [{"name": "ground", "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]},
           {"name": "ball", "type": "sphere", "centre": [-1.6, 0.8, 0], "radius": 0.8},
           {"name": "disk", "type": "disk", "centre": [1.5, 0.9, -1], "normal": [0.3, 0.4, 1], "radius": 0.7},
           {"name": "card", "type": "quad", "centre": [0.2, 0.6, 1.6], "halfEdges": [[0.6, 0, 0.2], [0, 0.5, 0]]},
           {"name": "crate", "type": "box", "min": [-0.4, 0, -2.5], "max": [0.6, 1.2, -1.5]},
           {"name": "tilted", "type": "box", "centre": [0, 0, 0], "halfExtents": [0.3, 0.3, 0.3],
            "transform": {"translate": [1.8, 0.45, 1.2], "rotateDegrees": {"axis": [1, 1, 0], "angle": 35}}}])

    exponents = [-3, -1, 1, 3, 5, 6]
    scales = [(e, 10.0 ** e) for e in exponents]

    def g(x):  # shortest decimal: 0.02, not 0.020000000000000004
        return float("%.12g" % x)
    write("spheres_across_scales",
          "Spheres 1e-3 to 1e6 units across, each seen by its own camera from three diameters away with near "
          "and far scaled to match; sphere k sits 10 diameters from the origin along x, so the big ones are also "
          "far from the origin. The stable quadratic (CPU and GLSL) keeps every scale equally accurate.",
          [perspective("d1e%d" % e, (g(10 * d), g(0.2 * d), g(3 * d)), (g(10 * d), 0, 0), 40, g(d / 100),
                       g(10 * d)) for e, d in scales],
          [{"name": "sphere_d1e%d" % e, "type": "sphere", "centre": [g(10 * d), 0, 0], "radius": g(d / 2)}
           for e, d in scales])

    write("sphere_touching_near",
          "Two spheres at the near plane (0.1): one tangent to it, one cut by it. Where the near plane cuts, the "
          "ray starts inside the sphere and both sides must show the far side (the exit root), not a hole.",
          [perspective("main", (0, 0, 0), (0, 0, -1), 60, 0.1, 50)],
          [{"name": "tangent", "type": "sphere", "centre": [-0.6, 0, -1.1], "radius": 1.0},
           {"name": "cut", "type": "sphere", "centre": [0.35, 0.1, -0.3], "radius": 0.3},
           {"name": "backdrop", "type": "quad", "centre": [0, 0, -6], "halfEdges": [[5, 0, 0], [0, 4, 0]]}])

    write("box_edge_on",
          "Boxes seen edge-on: the eye lies in the plane of the axis-aligned box's top face and of its side face, "
          "and a box rotated 45 degrees points an edge at the camera. Faces seen exactly edge-on cover no pixel "
          "centre on either side.",
          [perspective("main", (0.5, 1.0, 6), (0.5, 1.0, 0), 40, 0.1, 100)],
          [{"name": "level", "type": "box", "min": [-1, 0, -1], "max": [0.5, 1, 1]},
           {"name": "diamond", "type": "box", "centre": [0, 0, 0], "halfExtents": [0.5, 0.5, 0.5],
            "transform": {"translate": [1.6, 0.2, -1], "rotateDegrees": {"axis": [0, 1, 0], "angle": 45}}},
           {"name": "wall", "type": "quad", "centre": [0, 0, -4], "halfEdges": [[6, 0, 0], [0, 4, 0]]}])

    write("nested_spheres",
          "A sphere inside a larger one (inner radius 0.6, outer 1): the inner id must never appear on either side.",
          [perspective("main", (0.3, 0.5, 3.5), (0, 0, 0), 45, 0.1, 100)],
          [{"name": "outer", "type": "sphere", "centre": [0, 0, 0], "radius": 1.0},
           {"name": "inner", "type": "sphere", "centre": [0.1, 0, 0.2], "radius": 0.6}])

    write("terrain_100k",
          "A terrain-like heightfield of 100,352 triangles (fixed seed, generated by clipray itself: "
          "clipray/scene/Terrain.cpp), for timing a reconcile on a large mesh; the same terrain as "
          "clipray_intersect_bench.",
          [perspective("main", (0, 28, 62), (0, 0, -8), 55, 0.1, 1000)],
          [{"name": "terrain", "type": "terrain", "triangles": 100000, "seed": 0}])

    write_gltf_asset()
    write("gltf_asset",
          "A glTF 2.0 asset (assets/lantern.gltf: embedded buffer, a node hierarchy with TRS and matrix "
          "transforms, indexed and non-indexed primitives) reconciled from its own two cameras: a perspective "
          "one without zfar (infinite far) and an orthographic one. clipray reconcile scenes/assets/lantern.gltf "
          "does the same from the file alone.",
          [], [{"name": "lantern", "type": "meshFile", "path": "assets/lantern.gltf", "useCameras": True}])


def write_gltf_asset():
    """scenes/assets/lantern.gltf: float32 positions, uint16 indices, one base64 buffer."""
    import base64
    import struct
    ball = icosphere("ball", (0, 0, 0), 0.6, 2)
    ball_positions, ball_indices = ball["positions"], ball["indices"]
    # A base (a flattened box) drawn without indices: 12 triangles, 36 vertices.
    sx, sy, sz = 1.2, 0.15, 1.2
    corners = [(x, y, z) for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    base_positions = []
    for a, b, c, d in faces:
        for i in (a, b, c, a, c, d):
            base_positions += corners[i]
    blobs, views, accessors = b"", [], []

    def add(data, target, component, count, kind, extent=None):
        nonlocal blobs
        while len(blobs) % 4:
            blobs += b"\0"
        views.append({"buffer": 0, "byteOffset": len(blobs), "byteLength": len(data), "target": target})
        blobs += data
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
        if extent:
            accessor["min"], accessor["max"] = extent
        accessors.append(accessor)
        return len(accessors) - 1

    def extent(flat):
        xyz = [flat[i::3] for i in range(3)]
        return [float(struct.unpack("f", struct.pack("f", min(a)))[0]) for a in xyz], \
               [float(struct.unpack("f", struct.pack("f", max(a)))[0]) for a in xyz]

    ball_pos = add(struct.pack("<%df" % len(ball_positions), *ball_positions), 34962, 5126,
                   len(ball_positions) // 3, "VEC3", extent(ball_positions))
    ball_idx = add(struct.pack("<%dH" % len(ball_indices), *ball_indices), 34963, 5123, len(ball_indices),
                   "SCALAR")
    base_pos = add(struct.pack("<%df" % len(base_positions), *base_positions), 34962, 5126,
                   len(base_positions) // 3, "VEC3", extent(base_positions))
    half = math.radians(-12) / 2  # camera pitched down 12 degrees about x
    gltf = {
        "asset": {"version": "2.0", "generator": "clipray scenes/generate.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 3, 4]}],
        "nodes": [
            {"name": "lantern", "translation": [0.0, 0.15, 0.0], "rotation": [0.0, 0.3826834323650898, 0.0,
                                                                              0.9238795325112867],
             "scale": [1.0, 1.0, 1.0], "children": [1, 2]},
            {"name": "ball", "mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.2, 0.8, 0.1, 1]},
            {"name": "base", "mesh": 1},
            {"name": "perspective_camera", "camera": 0, "translation": [0.0, 1.6, 4.0],
             "rotation": [math.sin(half), 0.0, 0.0, math.cos(half)]},
            {"name": "orthographic_camera", "camera": 1, "translation": [0.0, 0.7, 6.0]},
        ],
        "meshes": [{"name": "ball", "primitives": [{"attributes": {"POSITION": ball_pos}, "indices": ball_idx,
                                                    "mode": 4}]},
                   {"name": "base", "primitives": [{"attributes": {"POSITION": base_pos}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.05, "aspectRatio": 4 / 3}},
                    {"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.5, "znear": 0.5,
                                                              "zfar": 20.0}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blobs),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blobs).decode()}],
    }
    os.makedirs(os.path.join(HERE, "assets"), exist_ok=True)
    with open(os.path.join(HERE, "assets", "lantern.gltf"), "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
