#!/usr/bin/python3
"""clipray's RenderDoc capture reader: `clipray check --capture` runs it on a .rdc file and reads
its standard output, one JSON object a line (as it reads `apitrace dump` text for --trace).

Debian ships RenderDoc's replay API only as this Python module (python3-renderdoc), so the
replay stays in this script and the C++ core parses its lines; no Python in the core.

  clipray-capture-reader.py CAPTURE.rdc
  clipray-capture-reader.py CAPTURE.rdc --depth-after EID[,EID...]   (check --capture --verify)
  clipray-capture-reader.py CAPTURE.rdc --geometry            (the draws' clip-space triangles)
  clipray-capture-reader.py CAPTURE.rdc --geometry --depth-after EID[,EID...]   (reconcile --capture)
  clipray-capture-reader.py CAPTURE.rdc --geometry-of EID[,EID...]  (those draws' triangles only)

Lines:
  {"kind": "capture", "api": "OpenGL" | "OpenGLES", "events": N, "draws": N}
  {"kind": "draw", "event": EID, "name": ..., "frame": F, "state": {...}, "calls": {...},
   "program": ..., "matrices": [...], "shaders": {...}}   one per draw, in event order
  {"kind": "error", "message": ...}                       then exit status 3
With --depth-after, instead of the draws, one line per EID: the draw framebuffer's depth
attachment as that event leaves it (mip 0, sample 0), as window depths:
  {"kind": "depth", "event": EID, "width": W, "height": H, "format": "32f" | "24" | "16",
   "samples": N,
   "depth": base64 of W*H little-endian float32, rows from the bottom}
  {"kind": "depth", "event": EID, "failure": "..."}       where it cannot be read
With --geometry, after the capture line, one line per draw: its vertex shader's output positions
(gl_Position, RenderDoc's post-VS data of instance 0), as triangles in clip coordinates:
  {"kind": "geometry", "event": EID, "depth_target": "...", "instances": N,
   "triangles": T, "clip": base64 of T*3 vertices x, y, z, w little-endian float32}
  {"kind": "geometry", "event": EID, "skipped": "..."}   not triangles, or no post-VS data
With both, the geometry lines come first, only for the EIDs --depth-after names (one replay
serves both).

Matrices are the vertex stage's float 4x4 variables of its uniform blocks ($Globals: the plain
uniforms) as GetCBufferVariableContents reports them, written as rows: RenderDoc 1.24 keeps a
matrix's values row by row whatever the GLSL layout (a column-major `uniform mat4` uploaded with
glUniformMatrix4fv(transpose = GL_FALSE) comes back with its w row last), so no std140 layout is
computed here. Calls are RenderDoc event IDs (EIDs) of the chunks that set each state, found by
walking the capture's chunks in event order.
"""

import base64
import json
import os
import re
import struct
import sys


def emit(line):
    sys.stdout.write(json.dumps(line, separators=(",", ":")) + "\n")


def fail(message):
    emit({"kind": "error", "message": message})
    sys.stdout.flush()
    sys.exit(3)


try:
    import renderdoc as rd
except ImportError as error:
    fail("RenderDoc's Python module is missing (" + str(error) +
         "): install Debian's python3-renderdoc (harness/install-deps.sh)")

COMPARE = {
    rd.CompareFunction.Never: "GL_NEVER",
    rd.CompareFunction.AlwaysTrue: "GL_ALWAYS",
    rd.CompareFunction.Less: "GL_LESS",
    rd.CompareFunction.LessEqual: "GL_LEQUAL",
    rd.CompareFunction.Greater: "GL_GREATER",
    rd.CompareFunction.GreaterEqual: "GL_GEQUAL",
    rd.CompareFunction.Equal: "GL_EQUAL",
    rd.CompareFunction.NotEqual: "GL_NOTEQUAL",
}
CULL = {
    rd.CullMode.NoCull: None,
    rd.CullMode.Front: "GL_FRONT",
    rd.CullMode.Back: "GL_BACK",
    rd.CullMode.FrontAndBack: "GL_FRONT_AND_BACK",
}
# The depth attachment's format as clipray names depth storage (TraceDepthState::depthFormatName).
DEPTH_FORMATS = {
    rd.ResourceFormatType.D16S8: "16",
    rd.ResourceFormatType.D24S8: "24",
    rd.ResourceFormatType.D32S8: "32f",
}
# The chunks that set each part of the state (their last EID before a draw is its call).
STATE_CHUNKS = {
    "glClipControl": "clip_control",
    "glDepthFunc": "depth_func",
    "glDepthRange": "depth_range", "glDepthRangef": "depth_range",
    "glDepthRangeIndexed": "depth_range", "glDepthRangeArrayv": "depth_range",
    "glCullFace": "cull_face_mode",
    "glFrontFace": "front_face",
    "glDepthMask": "depth_mask",
    "glPolygonOffset": "polygon_offset", "glPolygonOffsetClamp": "polygon_offset",
    "glPolygonOffsetClampEXT": "polygon_offset",
}
CAPS = {"GL_CULL_FACE": "cull_face", "GL_DEPTH_CLAMP": "depth_clamp",
        "GL_DEPTH_TEST": "depth_test", "GL_POLYGON_OFFSET_FILL": "polygon_offset_fill"}
CLEAR_DEPTH = re.compile(r"Depth = <([-+0-9.eEinfa]+)>")


def depth_format(controller, textures, resource):
    if resource == rd.ResourceId.Null():
        return "none"
    texture = textures.get(resource)
    if texture is None:
        return "unknown"
    fmt = texture.format
    if fmt.type in DEPTH_FORMATS:
        return DEPTH_FORMATS[fmt.type]
    # RenderDoc's GL driver names GL_DEPTH_COMPONENT16/24/32F as D16/D24/D32 (regular formats of
    # the Depth component type, 2, 3 and 4 bytes wide); a 4-byte depth is GL's float one.
    if fmt.compType == rd.CompType.Depth:
        return {2: "16", 3: "24", 4: "32f"}.get(fmt.compByteWidth, "unknown")
    return "unknown"


def matrices_of(controller, pipe, state):
    reflection = pipe.GetShaderReflection(rd.ShaderStage.Vertex)
    if reflection is None:
        return []
    found = []

    def collect(block, prefix, variables):
        for variable in variables:
            name = prefix + variable.name
            if len(variable.members) > 0:
                collect(block, name + ".", variable.members)
            elif (variable.rows == 4 and variable.columns == 4 and
                  variable.type == rd.VarType.Float):
                values = list(variable.value.f32v[:16])
                found.append({"block": block.name, "buffer_backed": bool(block.bufferBacked),
                              "name": name,
                              "rows": [values[r * 4:r * 4 + 4] for r in range(4)]})

    entry = pipe.GetShaderEntryPoint(rd.ShaderStage.Vertex)
    for index, block in enumerate(reflection.constantBlocks):
        bound = pipe.GetConstantBuffer(rd.ShaderStage.Vertex, index, 0)
        variables = controller.GetCBufferVariableContents(
            pipe.GetGraphicsPipelineObject(), reflection.resourceId, rd.ShaderStage.Vertex, entry,
            index, bound.resourceId, bound.byteOffset, bound.byteSize)
        collect(block, "", variables)
    return found


def shader_text(pipe, stage):
    reflection = pipe.GetShaderReflection(stage)
    if reflection is None:
        return None
    return "\n".join(f.contents for f in reflection.debugInfo.files)


def main():
    depth_events = None
    geometry = False
    geometry_events = None
    words = sys.argv[2:]

    def event_list(option, text):
        try:
            return [int(e) for e in text.split(",")]
        except ValueError:
            fail(option + ": expected event IDs separated by commas, got " + text)

    while words:
        if words[0] == "--geometry":
            geometry = True
            words = words[1:]
        elif words[0] == "--geometry-of" and len(words) > 1:
            geometry = True
            geometry_events = event_list(words[0], words[1])
            words = words[2:]
        elif words[0] == "--depth-after" and len(words) > 1:
            depth_events = event_list(words[0], words[1])
            words = words[2:]
        else:
            fail("usage: clipray-capture-reader.py CAPTURE.rdc [--geometry | --geometry-of "
                 "EID[,EID...]] [--depth-after EID[,EID...]]")
    if len(sys.argv) < 2:
        fail("usage: clipray-capture-reader.py CAPTURE.rdc [--geometry] "
             "[--depth-after EID[,EID...]]")
    state_only = depth_events is None and not geometry
    path = sys.argv[1]
    # Headless replay on Mesa (llvmpipe without a GPU): EGL's surfaceless platform.
    os.environ.setdefault("EGL_PLATFORM", "surfaceless")
    rd.InitialiseReplay(rd.GlobalEnvironment(), [])
    capture = rd.OpenCaptureFile()
    try:
        result = capture.OpenFile(path, "", None)
        if result.code == rd.ResultCode.FileCorrupted:
            fail(path + ": a truncated or corrupted capture (RenderDoc: " + result.Message() + ")")
        if result.code != rd.ResultCode.Succeeded:
            fail(path + ": not a RenderDoc capture (RenderDoc: " + result.Message() + ")")
        api = capture.DriverName()
        # RenderDoc's GL driver captures GLES through EGL too (its DriverName "OpenGLES"): the
        # same pipeline state (GetGLPipelineState), no clip control (lower-left, -1 to 1).
        if api not in ("OpenGL", "OpenGLES"):
            fail(path + ": a " + api +
                 " capture: clipray checks OpenGL and OpenGL ES captures only")
        if capture.LocalReplaySupport() != rd.ReplaySupport.Supported:
            fail(path + ": RenderDoc cannot replay this " + api +
                 " capture here (replay support: " + str(capture.LocalReplaySupport()) + ")")
        options = rd.ReplayOptions()
        # Only state and uniforms are read: the replay need not keep resources' contents between
        # events (half the time to open a small capture on llvmpipe). Depth is read as replayed.
        if state_only:
            options.optimisation = rd.ReplayOptimisationLevel.Fastest
        result, controller = capture.OpenCapture(options, None)
        if result.code != rd.ResultCode.Succeeded:
            fail(path + ": RenderDoc cannot replay the capture (" + result.Message() + ")")
        try:
            if state_only:
                read(path, api, controller)
            if geometry:
                read_geometry(api, controller,
                              geometry_events if geometry_events is not None else depth_events)
            for event in depth_events or []:
                emit(depth_line(controller, event))
        finally:
            controller.Shutdown()
    finally:
        capture.Shutdown()
        rd.ShutdownReplay()


def capture_actions(api, controller):
    """Every action in event order, and the draws among them; emits the capture line."""
    actions = []

    def walk(level):
        for action in level:
            actions.append(action)
            walk(action.children)

    walk(controller.GetRootActions())
    draws = [a for a in actions if a.flags & rd.ActionFlags.Drawcall]
    emit({"kind": "capture", "api": api, "events": actions[-1].eventId if actions else 0,
          "draws": len(draws)})
    return actions, draws


def read(path, api, controller):
    structured = controller.GetStructuredFile()
    actions, _ = capture_actions(api, controller)
    textures = {t.resourceId: t for t in controller.GetTextures()}
    programs = {r.resourceId: r.name for r in controller.GetResources()}
    calls = {}
    enabled = {}
    # The last depth clear of each depth attachment: (its EID, the value), so that a draw is
    # paired with the clear of the buffer it draws into, not of another pass's.
    clears = {}
    frame = 0
    for action in actions:
        for event in action.events:
            chunk = structured.chunks[event.chunkIndex]
            part = STATE_CHUNKS.get(chunk.name)
            if part:
                calls[part] = event.eventId
            elif chunk.name in ("glEnable", "glDisable") and chunk.NumChildren() > 0:
                cap = chunk.GetChild(0).AsString()
                if cap in CAPS:
                    calls[CAPS[cap]] = event.eventId
                    enabled[CAPS[cap]] = chunk.name == "glEnable"
                elif cap.startswith("GL_CLIP_DISTANCE"):
                    calls["clip_distances"] = event.eventId
        if action.flags & rd.ActionFlags.Clear:
            found = CLEAR_DEPTH.search(action.GetName(structured))
            if found:
                clears[str(action.depthOut)] = (action.eventId, float(found.group(1)))
        if action.flags & rd.ActionFlags.Drawcall:
            clear = clears.get(str(action.depthOut))
            draw_calls = dict(calls)
            if clear:
                draw_calls["clear"] = clear[0]
            emit(draw_line(controller, structured, action, frame, draw_calls, enabled,
                           clear[1] if clear else None, textures, programs))
        if action.flags & rd.ActionFlags.Present:
            frame += 1


def draw_line(controller, structured, action, frame, calls, enabled, cleared, textures,
              programs):
    controller.SetFrameEvent(action.eventId, True)
    gl = controller.GetGLPipelineState()
    pipe = controller.GetPipelineState()
    raster = gl.rasterizer.state
    viewport = gl.rasterizer.viewports[0]
    state = {
        "clip_lower_left": bool(gl.vertexProcessing.clipOriginLowerLeft),
        "clip_negative_one_to_one": bool(gl.vertexProcessing.clipNegativeOneToOne),
        "depth_test": bool(gl.depthState.depthEnable),
        "depth_func": COMPARE.get(gl.depthState.depthFunction, "unknown"),
        "depth_write": bool(gl.depthState.depthWrites),
        "depth_range": [viewport.minDepth, viewport.maxDepth],
        "viewport": [viewport.x, viewport.y, viewport.width, viewport.height],
        "cull_face": CULL.get(raster.cullMode),
        "front_ccw": bool(raster.frontCCW),
        "depth_clamp": bool(raster.depthClamp),
        "clip_distances": sum(1 << i for i, on in enumerate(gl.vertexProcessing.clipPlanes) if on),
        "polygon_offset": {"factor": raster.slopeScaledDepthBias, "units": raster.depthBias,
                           "clamp": raster.offsetClamp},
        # GL_POLYGON_OFFSET_FILL as the capture's glEnable/glDisable calls left it; null where
        # none was captured (set before the capture began: RenderDoc's state does not say).
        "polygon_offset_fill": enabled.get("polygon_offset_fill"),
        "depth_format": depth_format(controller, textures,
                                     gl.framebuffer.drawFBO.depthAttachment.resourceId),
        "cleared_depth": cleared,
        "depth_target": str(action.depthOut),
    }
    program = gl.vertexShader.programResourceId
    return {
        "kind": "draw", "event": action.eventId, "name": action.GetName(structured),
        "frame": frame, "state": state, "calls": calls,
        "program": programs.get(program, str(program)),
        "matrices": matrices_of(controller, pipe, gl),
        "shaders": {"vertex": shader_text(pipe, rd.ShaderStage.Vertex),
                    "geometry": shader_text(pipe, rd.ShaderStage.Geometry),
                    "fragment": shader_text(pipe, rd.ShaderStage.Fragment)},
    }


TRIANGLE_TOPOLOGIES = (rd.Topology.TriangleList, rd.Topology.TriangleStrip,
                       rd.Topology.TriangleFan)


def triangle_corners(topology, count):
    """The vertex order of each triangle a draw of `count` vertices makes (GL 4.6 10.1): strips
    alternate their winding back, fans share the first vertex."""
    if topology == rd.Topology.TriangleList:
        return [(k, k + 1, k + 2) for k in range(0, count - 2, 3)]
    if topology == rd.Topology.TriangleStrip:
        return [(k, k + 1, k + 2) if k % 2 == 0 else (k + 1, k, k + 2) for k in range(count - 2)]
    return [(0, k + 1, k + 2) for k in range(count - 2)]


def read_geometry(api, controller, events):
    """Each draw's geometry line; only those of `events` where --depth-after names them."""
    _, draws = capture_actions(api, controller)
    for action in draws:
        if events is None or action.eventId in events:
            emit(geometry_line(controller, action))


def geometry_line(controller, action):
    controller.SetFrameEvent(action.eventId, True)
    line = {"kind": "geometry", "event": action.eventId}
    mesh = controller.GetPostVSData(0, 0, rd.MeshDataStage.VSOut)
    if mesh.vertexResourceId == rd.ResourceId.Null() or mesh.numIndices == 0:
        line["skipped"] = "no vertex shader output (RenderDoc's post-VS data is empty)"
        return line
    if mesh.topology not in TRIANGLE_TOPOLOGIES:
        line["skipped"] = "draws " + str(mesh.topology).split(".")[-1] + ", not triangles"
        return line
    if mesh.format.compCount != 4 or mesh.format.compByteWidth != 4:
        line["skipped"] = "gl_Position as " + mesh.format.Name() + ", not four floats"
        return line
    data = controller.GetBufferData(mesh.vertexResourceId, mesh.vertexByteOffset, 0)
    count = mesh.numIndices
    if mesh.indexResourceId != rd.ResourceId.Null() and mesh.indexByteStride in (1, 2, 4):
        raw = controller.GetBufferData(mesh.indexResourceId, mesh.indexByteOffset, 0)
        code = {1: "B", 2: "H", 4: "I"}[mesh.indexByteStride]
        indices = struct.unpack("<%d%s" % (len(raw) // mesh.indexByteStride, code),
                                raw[:len(raw) - len(raw) % mesh.indexByteStride])[:count]
        indices = [i + mesh.baseVertex for i in indices]
    else:
        indices = list(range(count))
    clip = []
    for corners in triangle_corners(mesh.topology, len(indices)):
        for corner in corners:
            clip.extend(struct.unpack_from("<4f", data, indices[corner] * mesh.vertexByteStride))
    gl = controller.GetGLPipelineState()
    line.update({"depth_target": str(gl.framebuffer.drawFBO.depthAttachment.resourceId),
                 "instances": action.numInstances, "triangles": len(clip) // 12,
                 "clip": base64.b64encode(struct.pack("<%df" % len(clip), *clip)).decode()})
    return line


def decode_depth(texture, data):
    """Window depths from GetTextureData's bytes of a depth texture: float32 for D32 (D32S8:
    the float, then the stencil word), unsigned normalized for D16 and D24 (D24S8 packs depth in
    the upper 24 bits of each word, GL_UNSIGNED_INT_24_8's layout)."""
    fmt = texture.format
    count = texture.width * texture.height
    width = len(data) // count if count else 0
    if fmt.type == rd.ResourceFormatType.D32S8 or (fmt.compType == rd.CompType.Depth and
                                                   fmt.compByteWidth == 4):
        step = width // 4
        values = struct.unpack("<%df" % (count * step), data[:count * width])
        return list(values[::step]), "32f"
    if fmt.type == rd.ResourceFormatType.D24S8 or (fmt.compType == rd.CompType.Depth and
                                                   fmt.compByteWidth == 3):
        words = struct.unpack("<%dI" % count, data[:count * 4])
        return [(w >> 8) / 16777215.0 for w in words], "24"
    if fmt.type == rd.ResourceFormatType.D16S8 or (fmt.compType == rd.CompType.Depth and
                                                   fmt.compByteWidth == 2):
        step = width // 2
        values = struct.unpack("<%dH" % (count * step), data[:count * width])
        return [v / 65535.0 for v in values[::step]], "16"
    return None, fmt.Name()


def depth_line(controller, event):
    controller.SetFrameEvent(event, True)
    gl = controller.GetGLPipelineState()
    resource = gl.framebuffer.drawFBO.depthAttachment.resourceId
    line = {"kind": "depth", "event": event}
    if resource == rd.ResourceId.Null():
        line["failure"] = "the draw framebuffer has no depth attachment at event " + str(event)
        return line
    texture = next((t for t in controller.GetTextures() if t.resourceId == resource), None)
    if texture is None:
        line["failure"] = "RenderDoc lists no texture for the depth attachment"
        return line
    data = controller.GetTextureData(resource, rd.Subresource(0, 0, 0))
    depth, name = decode_depth(texture, bytes(data))
    if depth is None:
        line["failure"] = "a depth attachment of format " + name + " is not read"
        return line
    # The decoding checked against RenderDoc's own reading of one pixel (its centre).
    x, y = texture.width // 2, texture.height // 2
    picked = controller.PickPixel(resource, x, y, rd.Subresource(0, 0, 0), rd.CompType.Depth)
    expected = picked.floatValue[0]
    # GetTextureData's rows run from the bottom (GL's) or from the top; the pick is in RenderDoc's
    # top-down texel coordinates.
    bottom_up = depth[(texture.height - 1 - y) * texture.width + x]
    top_down = depth[y * texture.width + x]
    tolerance = 2.0 ** -23 if name == "32f" else 2.0 ** -15
    if abs(top_down - expected) <= tolerance and abs(bottom_up - expected) > tolerance:
        rows = [depth[r * texture.width:(r + 1) * texture.width] for r in range(texture.height)]
        depth = [v for row in reversed(rows) for v in row]
    elif abs(bottom_up - expected) > tolerance:
        line["failure"] = ("the decoded depth %.9g at texel (%d, %d) is not RenderDoc's %.9g" %
                           (bottom_up, x, y, expected))
        return line
    line.update({"width": texture.width, "height": texture.height, "format": name,
                 "samples": texture.msSamp,
                 "depth": base64.b64encode(struct.pack("<%df" % len(depth), *depth)).decode()})
    return line


if __name__ == "__main__":
    main()
