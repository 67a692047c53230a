#!/usr/bin/env python3
"""Writes the mesh files tests/unit/MeshFileTest.cpp loads (python3 stdlib only).

Every coordinate is a small dyadic number so that the transformed positions the tests expect are
exact in double. Run from anywhere: files are written next to this script.
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# A unit quad in z = 0 (indexed) and one triangle (not indexed).
QUAD_POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
QUAD_INDICES = [0, 1, 2, 0, 2, 3]
TRIANGLE_POSITIONS = [(0, 0, 0), (2, 0, 0), (0, 2, 0)]


def floats(points):
    return b"".join(struct.pack("<3f", *p) for p in points)


def pad4(data):
    return data + b"\0" * (-len(data) % 4)


def hierarchy_gltf(buffer_uri, buffer_length):
    """Quad under a TRS parent, triangle under a matrix node, three cameras."""
    quad_bytes = len(floats(QUAD_POSITIONS))
    index_bytes = 2 * len(QUAD_INDICES)
    return {
        "asset": {"version": "2.0", "generator": "clipray tests/data/meshes/generate.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 2, 3, 4, 5]}],
        "nodes": [
            # Rotation by 180 degrees about z (x, y, z, w) keeps every product exact.
            {"name": "parent", "translation": [1, 2, 3], "rotation": [0, 0, 1, 0],
             "scale": [2, 2, 2], "children": [1]},
            {"name": "quad", "translation": [0, 0, -1], "mesh": 0},
            {"name": "triangle", "mesh": 1,
             "matrix": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 10, 20, 30, 1]},
            {"name": "persp", "translation": [0, 0, 5], "camera": 0},
            {"translation": [0, 1, 0], "camera": 1},
            {"name": "ortho", "translation": [0, 0, 8], "camera": 2},
        ],
        "cameras": [
            {"type": "perspective",
             "perspective": {"yfov": 0.5, "znear": 0.25, "zfar": 100}},
            {"type": "perspective",
             "perspective": {"yfov": 1.0, "aspectRatio": 1.5, "znear": 0.5}},
            {"type": "orthographic",
             "orthographic": {"xmag": 3, "ymag": 2, "znear": 0, "zfar": 16}},
        ],
        "meshes": [
            {"name": "Quad", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
            {"name": "Triangle", "primitives": [{"attributes": {"POSITION": 2}, "mode": 4}]},
        ],
        "buffers": [{"uri": buffer_uri, "byteLength": buffer_length}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": quad_bytes},
            {"buffer": 0, "byteOffset": quad_bytes, "byteLength": index_bytes},
            {"buffer": 0, "byteOffset": quad_bytes + len(pad4(b"\0" * index_bytes)),
             "byteLength": len(floats(TRIANGLE_POSITIONS))},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [2, 2, 0]},
        ],
    }


def hierarchy_buffer():
    indices = struct.pack("<6H", *QUAD_INDICES)
    return floats(QUAD_POSITIONS) + pad4(indices) + floats(TRIANGLE_POSITIONS)


def write_json(name, document):
    with open(os.path.join(HERE, name), "w", encoding="utf-8") as f:
        json.dump(document, f, indent=1)
        f.write("\n")


def write_bytes(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def gltf_files():
    buffer = hierarchy_buffer()
    write_bytes("hierarchy.bin", buffer)
    write_json("hierarchy.gltf", hierarchy_gltf("hierarchy.bin", len(buffer)))

    # The same scene with the buffer embedded and no "scenes": every root node is loaded.
    embedded = hierarchy_gltf(
        "data:application/octet-stream;base64," + base64.b64encode(buffer).decode(), len(buffer))
    del embedded["scene"]
    del embedded["scenes"]
    write_json("embedded.gltf", embedded)

    # A GLB with interleaved vertices (16-byte stride: position + 4 bytes of padding), 32-bit
    # indices and one degenerate triangle (two equal corners), kept and warned about.
    positions = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (4, 4, 0)]
    vertex_bytes = b"".join(struct.pack("<3fI", *p, 0xDEADBEEF) for p in positions)
    index_bytes = struct.pack("<6I", 0, 1, 2, 1, 1, 3)
    binary = vertex_bytes + index_bytes
    document = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, -2]}],
        "meshes": [{"name": "Strided", "primitives": [{"attributes": {"POSITION": 0},
                                                     "indices": 1}]}],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(vertex_bytes), "byteStride": 16},
            {"buffer": 0, "byteOffset": len(vertex_bytes), "byteLength": len(index_bytes)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [4, 4, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
    }
    json_chunk = json.dumps(document).encode()
    json_chunk += b" " * (-len(json_chunk) % 4)
    bin_chunk = pad4(binary)
    total = 12 + 8 + len(json_chunk) + 8 + len(bin_chunk)
    glb = struct.pack("<4sII", b"glTF", 2, total)
    glb += struct.pack("<I4s", len(json_chunk), b"JSON") + json_chunk
    glb += struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk
    write_bytes("strided.glb", glb)


def obj_files():
    # Two quads, the second written with relative (negative) indices and v/vt/vn triples.
    text = """# two quads: absolute and relative indices
o first
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f 1 2 3 4
o second
v 0 0 1
v 2 0 1
v 2 2 1
v 0 2 1
vt 0 0
vn 0 0 1
f -4/1/1 -3/1/1 -2/1/1 -1/1/1
"""
    with open(os.path.join(HERE, "quads.obj"), "w", encoding="ascii") as f:
        f.write(text)


# PLY: a quad face and a triangle face over five vertices, with properties and an element the
# reader must skip.
PLY_POSITIONS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
PLY_FACES = [[0, 1, 2, 3], [0, 1, 4]]


def ply_ascii():
    lines = ["ply", "format ascii 1.0", "comment written by generate.py",
             "element vertex 5", "property float x", "property float y", "property float z",
             "property uchar red", "element face 2", "property uchar flags",
             "property list uchar int vertex_indices", "element edge 1",
             "property list uchar int vertex_pair", "end_header"]
    for i, (x, y, z) in enumerate(PLY_POSITIONS):
        lines.append(f"{x:g} {y:g} {z:g} {i * 10}")
    for face in PLY_FACES:
        lines.append("7 " + str(len(face)) + " " + " ".join(map(str, face)))
    lines.append("2 0 1")
    return ("\n".join(lines) + "\n").encode()


def ply_binary(endian, name):
    big = endian == ">"
    header = ["ply", "format binary_big_endian 1.0" if big else "format binary_little_endian 1.0",
              "element vertex 5",
              "property double x" if big else "property float x",
              "property short skipped",
              "property double y" if big else "property float y",
              "property double z" if big else "property float z",
              "element face 2",
              "property list ushort uint vertex_index" if big
              else "property list uchar int vertex_indices",
              "property float quality",
              "element edge 1", "property list uchar int vertex_pair",
              "end_header"]
    body = b""
    coordinate = "d" if big else "f"
    for i, (x, y, z) in enumerate(PLY_POSITIONS):
        body += struct.pack(endian + coordinate, x) + struct.pack(endian + "h", -i)
        body += struct.pack(endian + 2 * coordinate, y, z)
    for face in PLY_FACES:
        if big:
            body += struct.pack(endian + "H", len(face)) + struct.pack(endian + f"{len(face)}I", *face)
        else:
            body += struct.pack(endian + "B", len(face)) + struct.pack(endian + f"{len(face)}i", *face)
        body += struct.pack(endian + "f", 0.5)
    body += struct.pack(endian + "B2i", 2, 0, 1)
    write_bytes(name, ("\n".join(header) + "\n").encode() + body)


def ply_files():
    write_bytes("ascii.ply", ply_ascii())
    ply_binary("<", "binary_little.ply")
    ply_binary(">", "binary_big.ply")


if __name__ == "__main__":
    gltf_files()
    obj_files()
    ply_files()
