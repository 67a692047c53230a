// The recorder script (PageRecorder.hpp). It runs before any of the page's scripts, so every
// context the page creates is made through the wrapped HTMLCanvasElement.prototype.getContext and
// every call goes through the wrapped prototype methods. Calls of contexts it did not see created
// (an OffscreenCanvas's) are not kept.
//
// Each kept call is [context index, name, arguments...] with WebGL objects replaced by a number
// of their own (WeakMap): programs, uniform locations, framebuffers, renderbuffers and textures.
// A frame is one requestAnimationFrame tick: the recorder's own callback, registered first, runs
// first in each tick (HTML, "run the animation frame callbacks": in the order registered) and
// records the end of the previous frame, [-1, "frame"], before any of the page's callbacks draws.
//
// Memory is bounded: past kMaxCalls the calls are counted, not kept.

#include "clipray/page/PageRecorder.hpp"

namespace clipray::page {

namespace {

// Called with the number of frames to record (PageRecorder.hpp).
constexpr std::string_view kScript = R"js(
((frameLimit, verify, withThree, toggleReversedDepth) => {
  'use strict';
  if (window.__clipray) return;
  const kMaxCalls = 500000;
  // done: frameLimit frames are recorded; nothing more is kept.
  const rec = {calls: [], frames: 0, draws: 0, dropped: 0, done: false, contexts: [], errors: [],
               pageErrors: []};
  const canvases = [];
  // The page's own uncaught errors: why a page never drew, often.
  const pageError = (text) => {
    if (rec.pageErrors.length < 10) rec.pageErrors.push(String(text));
  };
  window.addEventListener('error', (event) => pageError(event.message));
  window.addEventListener('unhandledrejection', (event) =>
    pageError('unhandled rejection: ' + (event.reason && event.reason.message || event.reason)));
  Object.defineProperty(window, '__clipray', {value: rec});

  // Numbers from 1 for each kind of object (WebGLProgram, WebGLShader, WebGLBuffer, ...), as a
  // GL app's names would be: "program 1" is the page's first program.
  const ids = new WeakMap();
  const counters = new Map();
  const idOf = (object) => {
    if (object === null || object === undefined) return 0;
    let id = ids.get(object);
    if (id === undefined) {
      const kind = Object.prototype.toString.call(object);
      id = (counters.get(kind) || 0) + 1;
      counters.set(kind, id);
      ids.set(object, id);
    }
    return id;
  };
  const contextIndex = new WeakMap();  // context or extension object -> index in rec.contexts
  // Per context: EXT_clip_control's depth mode (GL's NEGATIVE_ONE_TO_ONE 0x935E until
  // clipControlEXT), the depth clear value and the depth range, as the page's last calls left them.
  const depthStates = [];
  const keep = (owner, name, args) => {
    const index = contextIndex.get(owner);
    if (index === undefined || rec.done) return false;
    if (rec.calls.length >= kMaxCalls) {
      rec.dropped++;
      return false;
    }
    rec.calls.push([index, name, ...args]);
    return true;
  };
  const wrap = (target, name, record) => {
    const original = target[name];
    if (typeof original !== 'function') return;
    target[name] = function(...args) {
      const result = original.apply(this, args);
      try {
        record(this, args, result);
      } catch (error) {
        if (rec.errors.length < 10) rec.errors.push(name + ': ' + error);
      }
      return result;
    };
  };
  // WebGL2's *fv calls take (data, srcOffset, srcLength) (WebGL 2.0, 3.7.8).
  const values = (data, offset, length) => {
    const all = Array.from(data, Number);
    const from = offset || 0;
    return all.slice(from, length ? from + length : undefined);
  };

  // A buffer's bytes (WebGL 2.0, 3.7.3: srcOffset and length count elements of the view), as
  // base64; null past kMaxBufferBytes (not a uniform block: GL_MAX_UNIFORM_BLOCK_SIZE is 64 KiB on
  // common implementations) or for what is no buffer.
  const kMaxBufferBytes = 1 << 20;
  const bytesOf = (data, offset, length) => {
    let view = null;
    if (data instanceof ArrayBuffer) {
      view = new Uint8Array(data);
    } else if (ArrayBuffer.isView(data)) {
      const size = data.BYTES_PER_ELEMENT || 1;
      const start = data.byteOffset + (offset || 0) * size;
      const end = length ? start + length * size : data.byteOffset + data.byteLength;
      if (end < start || end > data.byteOffset + data.byteLength) return null;
      view = new Uint8Array(data.buffer, start, end - start);
    }
    return view && view.length <= kMaxBufferBytes ? view : null;
  };
  const base64 = (bytes) => {
    let text = '';
    for (let k = 0; k < bytes.length; k += 8192) {
      text += String.fromCharCode.apply(null, bytes.subarray(k, k + 8192));
    }
    return btoa(text);
  };
  const kUniformBuffer = 0x8A11;
  const kDepthTest = 0x0B71, kCullFace = 0x0B44, kPolygonOffsetFill = 0x8037;
  const kDepth = 0x1801, kDepthStencil = 0x84F9;
  const draw = (name) => (owner) => {
    if (keep(owner, name, [])) rec.draws++;
  };
  const prototypes = [];
  if (typeof WebGLRenderingContext !== 'undefined') prototypes.push(WebGLRenderingContext.prototype);
  if (typeof WebGL2RenderingContext !== 'undefined') {
    prototypes.push(WebGL2RenderingContext.prototype);
  }
  for (const proto of prototypes) {
    const capability = (name) => (gl, [cap]) => {
      if (cap === kDepthTest || cap === kCullFace || cap === kPolygonOffsetFill) keep(gl, name, [cap]);
    };
    wrap(proto, 'enable', capability('enable'));
    wrap(proto, 'disable', capability('disable'));
    // The clear value and depth range as the last call left them, kept past the recording's
    // end (reconcile --page maps a pick to window depth with them).
    wrap(proto, 'clearDepth', (gl, [depth]) => {
      if (contextIndex.has(gl)) depthStates[contextIndex.get(gl)].clearDepth = Math.min(1, Math.max(0, Number(depth)));
    });
    wrap(proto, 'depthRange', (gl, [near, far]) => {
      // WebGL 1.0, 6.12: near above far is refused (INVALID_OPERATION), nothing changes.
      if (contextIndex.has(gl) && !(near > far)) {
        depthStates[contextIndex.get(gl)].depthRange = [Number(near), Number(far)];
      }
    });
    for (const name of ['depthFunc', 'clearDepth', 'depthRange', 'viewport', 'cullFace',
                        'frontFace', 'depthMask', 'polygonOffset', 'clear']) {
      wrap(proto, name, (gl, args) => keep(gl, name, args.map(Number)));
    }
    wrap(proto, 'clearBufferfv', (gl, [buffer, drawBuffer, data, offset]) => {
      if (buffer === kDepth) keep(gl, 'clearBufferfv', [buffer, drawBuffer, values(data, offset)[0]]);
    });
    wrap(proto, 'clearBufferfi', (gl, [buffer, drawBuffer, depth, stencil]) => {
      if (buffer === kDepthStencil) keep(gl, 'clearBufferfi', [buffer, drawBuffer, depth, stencil]);
    });
    wrap(proto, 'useProgram', (gl, [program]) => keep(gl, 'useProgram', [idOf(program)]));
    wrap(proto, 'linkProgram', (gl, [program]) => keep(gl, 'linkProgram', [idOf(program)]));
    wrap(proto, 'getUniformLocation', (gl, [program, name], location) => {
      if (location) keep(gl, 'getUniformLocation', [idOf(program), String(name), idOf(location)]);
    });
    wrap(proto, 'uniformMatrix4fv', (gl, [location, transpose, data, offset, length]) => {
      if (!location) return;
      // WebGL 1.0, 5.14.10: transpose must be false (INVALID_VALUE, nothing set); WebGL 2.0 allows
      // true as ES 3.0 does.
      if (transpose && !(gl instanceof WebGL2RenderingContext)) return;
      keep(gl, 'uniformMatrix4fv', [idOf(location), transpose ? 1 : 0, values(data, offset, length)]);
    });
    for (const name of ['drawArrays', 'drawElements', 'drawArraysInstanced',
                        'drawElementsInstanced', 'drawRangeElements']) {
      wrap(proto, name, draw(name));
    }
    wrap(proto, 'bindFramebuffer', (gl, [target, framebuffer]) =>
      keep(gl, 'bindFramebuffer', [target, idOf(framebuffer)]));
    wrap(proto, 'bindRenderbuffer', (gl, [target, renderbuffer]) =>
      keep(gl, 'bindRenderbuffer', [target, idOf(renderbuffer)]));
    wrap(proto, 'renderbufferStorage', (gl, [target, format]) =>
      keep(gl, 'renderbufferStorage', [target, format]));
    wrap(proto, 'renderbufferStorageMultisample', (gl, [target, samples, format]) =>
      keep(gl, 'renderbufferStorage', [target, format]));
    wrap(proto, 'framebufferRenderbuffer', (gl, [target, attachment, rbTarget, renderbuffer]) =>
      keep(gl, 'framebufferRenderbuffer', [target, attachment, rbTarget, idOf(renderbuffer)]));
    wrap(proto, 'framebufferTexture2D', (gl, [target, attachment, texTarget, texture, level]) =>
      keep(gl, 'framebufferTexture2D', [target, attachment, texTarget, idOf(texture), level]));
    wrap(proto, 'activeTexture', (gl, [unit]) => keep(gl, 'activeTexture', [unit]));
    wrap(proto, 'bindTexture', (gl, [target, texture]) =>
      keep(gl, 'bindTexture', [target, idOf(texture)]));
    wrap(proto, 'texImage2D', (gl, [target, level, format]) =>
      keep(gl, 'texImage2D', [target, level, format]));
    wrap(proto, 'texStorage2D', (gl, [target, levels, format]) =>
      keep(gl, 'texStorage2D', [target, levels, format]));
    // Uniform buffers (WebGL 2): the bindings of UNIFORM_BUFFER, the bytes written to it, the
    // shaders' text (the blocks' std140 layout) and the blocks' bindings.
    wrap(proto, 'bindBuffer', (gl, [target, buffer]) => {
      if (target === kUniformBuffer) keep(gl, 'bindBuffer', [target, idOf(buffer)]);
    });
    wrap(proto, 'bindBufferBase', (gl, [target, index, buffer]) => {
      if (target === kUniformBuffer) keep(gl, 'bindBufferBase', [target, index, idOf(buffer)]);
    });
    wrap(proto, 'bindBufferRange', (gl, [target, index, buffer, offset, size]) => {
      if (target === kUniformBuffer) {
        keep(gl, 'bindBufferRange', [target, index, idOf(buffer), offset, size]);
      }
    });
    wrap(proto, 'bufferData', (gl, [target, data, usage, offset, length]) => {
      if (target !== kUniformBuffer) return;
      if (typeof data === 'number') {
        keep(gl, 'bufferData', [target, data, null]);  // zero-filled (WebGL 1.0, 5.14.5)
      } else {
        const bytes = bytesOf(data, offset, length);
        if (bytes) keep(gl, 'bufferData', [target, bytes.length, base64(bytes)]);
      }
    });
    wrap(proto, 'bufferSubData', (gl, [target, dstOffset, data, offset, length]) => {
      if (target !== kUniformBuffer) return;
      const bytes = bytesOf(data, offset, length);
      if (bytes) keep(gl, 'bufferSubData', [target, dstOffset, bytes.length, base64(bytes)]);
    });
    wrap(proto, 'createShader', (gl, [type], shader) => {
      if (shader) keep(gl, 'createShader', [type, idOf(shader)]);
    });
    wrap(proto, 'shaderSource', (gl, [shader, source]) =>
      keep(gl, 'shaderSource', [idOf(shader), String(source)]));
    wrap(proto, 'attachShader', (gl, [program, shader]) =>
      keep(gl, 'attachShader', [idOf(program), idOf(shader)]));
    wrap(proto, 'detachShader', (gl, [program, shader]) =>
      keep(gl, 'detachShader', [idOf(program), idOf(shader)]));
    wrap(proto, 'getUniformBlockIndex', (gl, [program, name], index) =>
      keep(gl, 'getUniformBlockIndex', [idOf(program), String(name), index]));
    wrap(proto, 'uniformBlockBinding', (gl, [program, index, binding]) =>
      keep(gl, 'uniformBlockBinding', [idOf(program), index, binding]));
    // Extensions: EXT_clip_control's clipControlEXT (the only way a WebGL page gets a zero-to-one
    // clip volume), ANGLE_instanced_arrays' draws (WebGL 1).
    wrap(proto, 'getExtension', (gl, [name], extension) => {
      if (!extension || !contextIndex.has(gl) || contextIndex.has(extension)) return;
      contextIndex.set(extension, contextIndex.get(gl));
      const lower = String(name).toLowerCase();
      if (lower === 'ext_clip_control') {
        wrap(extension, 'clipControlEXT', (ext, [origin, depth]) => {
          depthStates[contextIndex.get(ext)].clipDepth = depth;
          keep(ext, 'clipControl', [origin, depth]);
        });
      } else if (lower === 'angle_instanced_arrays') {
        wrap(extension, 'drawArraysInstancedANGLE', draw('drawArraysInstanced'));
        wrap(extension, 'drawElementsInstancedANGLE', draw('drawElementsInstanced'));
      }
    });
  }

  const getContext = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function(type, ...rest) {
    const kind = String(type);
    const webgl = kind === 'webgl' || kind === 'webgl2' || kind === 'experimental-webgl';
    const asked = (rest[0] && typeof rest[0] === 'object') ? rest[0] : {};
    if (webgl && verify) {
      // --verify reads the depth buffer after the last frame: it must outlive the frame
      // (preserveDrawingBuffer) and be single-sampled (a blit copies it).
      rest[0] = Object.assign({}, asked, {preserveDrawingBuffer: true, antialias: false});
    }
    const gl = getContext.call(this, type, ...rest);
    if (gl && webgl && !contextIndex.has(gl)) {
      const index = rec.contexts.length;
      contextIndex.set(gl, index);
      canvases.push({canvas: this, gl});
      const attributes = gl.getContextAttributes() || {};
      depthStates.push({clipDepth: 0x935E, clearDepth: 1, depthRange: [0, 1],
                        subpixelBits: gl.getParameter(gl.SUBPIXEL_BITS)});
      rec.contexts.push({
        name: this.id ? 'canvas#' + this.id : 'canvas ' + (index + 1),
        type: kind,
        depth: !!attributes.depth,
        // What the page asked for (under --verify the context preserves it regardless).
        preserveDrawingBuffer: verify ? !!asked.preserveDrawingBuffer
                                      : !!attributes.preserveDrawingBuffer,
        depthBits: attributes.depth ? gl.getParameter(gl.DEPTH_BITS) : 0,
      });
      // WebGL 1.0, 5.13.4: the viewport starts as the drawing buffer's size.
      keep(gl, 'context', [gl.drawingBufferWidth, gl.drawingBufferHeight]);
    }
    return gl;
  };

  // The frames are counted from the page's first draw: frame 0 is everything up to the end of the
  // animation frame that drew first, frame k the k-th animation frame after it. Each frame's end
  // is recorded as [-1, "frame"], at the start of the next tick; after frameLimit frames the
  // recording is done.
  const tick = () => {
    if (rec.draws > 0 && !rec.done) {
      rec.frames++;
      if (rec.calls.length < kMaxCalls) rec.calls.push([-1, 'frame']);
      if (rec.frames >= frameLimit) {
        rec.done = true;
        return;
      }
    }
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);

  // --verify: each canvas's depth buffer as the last frame left it, as {width, height, format,
  // depth: base64 of float32s, bottom row first} or {failure}. WebGL cannot read depth with
  // readPixels; the depth is blitted into a depth texture of the drawing buffer's format, drawn
  // through texelFetch into an R32F target (EXT_color_buffer_float) and read as RGBA/FLOAT.
  const readDepth = (gl) => {
    if (typeof WebGL2RenderingContext === 'undefined' || !(gl instanceof WebGL2RenderingContext)) {
      return {failure: 'a WebGL 1 context (reading depth needs WebGL 2)'};
    }
    if (!gl.getContextAttributes().depth) return {failure: 'the context has no depth buffer'};
    if (!gl.getExtension('EXT_color_buffer_float')) return {failure: 'no EXT_color_buffer_float'};
    const width = gl.drawingBufferWidth, height = gl.drawingBufferHeight;
    while (gl.getError() !== gl.NO_ERROR) {}
    gl.bindVertexArray(gl.createVertexArray());
    for (const cap of [gl.DEPTH_TEST, gl.STENCIL_TEST, gl.BLEND, gl.CULL_FACE, gl.SCISSOR_TEST,
                       gl.RASTERIZER_DISCARD, gl.POLYGON_OFFSET_FILL]) {
      gl.disable(cap);
    }
    gl.colorMask(true, true, true, true);
    gl.activeTexture(gl.TEXTURE0);
    // The drawing buffer's depth format is not exposed: the blit succeeds only into the same one.
    let depthTexture = null, formatName = '';
    for (const [format, attachment, name] of [
             [gl.DEPTH24_STENCIL8, gl.DEPTH_STENCIL_ATTACHMENT, 'GL_DEPTH24_STENCIL8'],
             [gl.DEPTH_COMPONENT24, gl.DEPTH_ATTACHMENT, 'GL_DEPTH_COMPONENT24'],
             [gl.DEPTH_COMPONENT16, gl.DEPTH_ATTACHMENT, 'GL_DEPTH_COMPONENT16'],
             [gl.DEPTH_COMPONENT32F, gl.DEPTH_ATTACHMENT, 'GL_DEPTH_COMPONENT32F'],
             [gl.DEPTH32F_STENCIL8, gl.DEPTH_STENCIL_ATTACHMENT, 'GL_DEPTH32F_STENCIL8']]) {
      const texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.texStorage2D(gl.TEXTURE_2D, 1, format, width, height);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      const framebuffer = gl.createFramebuffer();
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, framebuffer);
      gl.framebufferTexture2D(gl.DRAW_FRAMEBUFFER, attachment, gl.TEXTURE_2D, texture, 0);
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, null);
      gl.blitFramebuffer(0, 0, width, height, 0, 0, width, height, gl.DEPTH_BUFFER_BIT,
                         gl.NEAREST);
      if (gl.getError() === gl.NO_ERROR) {
        depthTexture = texture;
        formatName = name;
        break;
      }
    }
    if (!depthTexture) return {failure: 'the drawing buffer\'s depth could not be copied'};
    const compile = (type, source) => {
      const shader = gl.createShader(type);
      gl.shaderSource(shader, source);
      gl.compileShader(shader);
      return shader;
    };
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl.VERTEX_SHADER, `#version 300 es
      void main() {
        gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);
      }`));
    gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `#version 300 es
      precision highp float;
      uniform highp sampler2D depth;
      out vec4 color;
      void main() { color = vec4(texelFetch(depth, ivec2(gl_FragCoord.xy), 0).r, 0.0, 0.0, 1.0); }`));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) return {failure: 'no depth read program'};
    const target = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, target);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.R32F, width, height);
    const framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
    gl.bindTexture(gl.TEXTURE_2D, depthTexture);
    gl.useProgram(program);
    gl.uniform1i(gl.getUniformLocation(program, 'depth'), 0);
    gl.viewport(0, 0, width, height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const pixels = new Float32Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.FLOAT, pixels);
    if (gl.getError() !== gl.NO_ERROR) return {failure: 'the depth could not be read back'};
    const depth = new Float32Array(width * height);
    for (let k = 0; k < depth.length; ++k) depth[k] = pixels[4 * k];
    return {width, height, format: formatName, depth: base64(new Uint8Array(depth.buffer))};
  };
  rec.readDepth = () => JSON.stringify(canvases.map(({gl}) => readDepth(gl)));

  // reconcile --page: three.js announces each WebGLRenderer and Scene it makes to
  // window.__THREE_DEVTOOLS__ (an 'observe' event carrying the object) when that exists before
  // three.js runs, and its REVISION with a 'register' event. Each observed renderer's render is
  // wrapped on the instance to keep the scene and camera it last drew.
  const three = {renderers: [], scenes: 0, revision: '', module: null, found: '', toggles: []};
  if (withThree && typeof window.__THREE_DEVTOOLS__ === 'undefined') {
    const devtools = new EventTarget();
    devtools.addEventListener('observe', (event) => {
      const object = event.detail;
      if (object && object.isWebGLRenderer && typeof object.render === 'function') {
        const entry = {renderer: object, scene: null, camera: null, renders: 0};
        three.renderers.push(entry);
        // The toggled run (PageToggle.hpp): the renderer announces itself at the end of its
        // constructor, after it has set up its state (and, asked for reversedDepthBuffer, turned
        // it on) and before it draws; flipping its depth buffer here is what the constructor's
        // parameter does (WebGLRenderer's initGLContext calls the same setReversed), and no
        // camera has been given a reversed projection yet. What happened is kept for the report.
        if (toggleReversedDepth) {
          try {
            const depth = object.state.buffers.depth;
            const was = depth.getReversed();
            if (!was && !object.extensions.has('EXT_clip_control')) {
              three.toggles.push({from: was, to: was, failure: 'no EXT_clip_control'});
            } else {
              depth.setReversed(!was);
              three.toggles.push({from: was, to: depth.getReversed()});
            }
          } catch (error) {
            three.toggles.push({failure: String(error)});
          }
        }
        const render = object.render;
        object.render = function(scene, camera) {
          if (scene && scene.isObject3D && camera && camera.isCamera) {
            entry.scene = scene;
            entry.camera = camera;
            entry.renders++;
          }
          return render.apply(this, arguments);
        };
      } else if (object && object.isScene) {
        three.scenes++;
      }
    });
    devtools.addEventListener('register', (event) => {
      three.revision = String(event.detail && event.detail.revision || '');
    });
    Object.defineProperty(window, '__THREE_DEVTOOLS__',
                          {value: devtools, configurable: true, writable: true});
  }
  // The renderer that drew last through a camera (the page's main view, where there are more).
  const drawingRenderer = () => {
    let best = null;
    for (const entry of three.renderers) {
      if (entry.camera && contextIndex.has(entry.renderer.getContext()) &&
          (!best || entry.renders >= best.renders)) {
        best = entry;
      }
    }
    return best;
  };
  // The page's own three.js module, the one whose classes made the renderer's scene: window.THREE
  // where the page sets it, else the module the page imported, by `importer` (import() from the
  // DevTools' evaluation: the page's import map applies), as 'three' and by the URLs of the
  // scripts it loaded. Returns '' when found, else why not.
  rec.findThree = async (importer) => {
    if (three.module) return '';
    if (three.renderers.length === 0) return 'no three.js renderer was observed';
    const entry = drawingRenderer();
    if (!entry) return 'no three.js renderer drew through a camera';
    const ours = (module) => module && typeof module.Raycaster === 'function' &&
                             typeof module.Object3D === 'function' &&
                             entry.scene instanceof module.Object3D;
    const candidates = [() => window.THREE, () => importer('three')];
    for (const resource of performance.getEntriesByType('resource')) {
      if (/three[^/]*\.m?js(\?|#|$)/.test(resource.name)) {
        candidates.push(() => importer(resource.name));
      }
    }
    for (const candidate of candidates) {
      try {
        const module = await candidate();
        if (ours(module)) {
          three.module = module;
          return '';
        }
      } catch (error) {
        // The next way.
      }
    }
    return 'the page\'s three.js module (its Raycaster) could not be reached';
  };
  // The page's own Raycaster.setFromCamera at the centres of a columns x rows grid of the
  // drawing buffer's pixels, each pick's first hit, and the depth buffer the last frame left,
  // read in the same task (no frame runs in between). A pick is [x, y (pixel, from the top),
  // hit: null or [point xyz, world normal xyz, object index], ambiguous]; ambiguous where the
  // rays 2^-SUBPIXEL_BITS of a pixel left, right, above and below the centre do not all reach
  // the same object (the rasterizer snaps vertices to that grid: an edge that near the centre
  // may cover it or not).
  rec.pick = (columns, rows) => {
    const entry = drawingRenderer();
    const THREE = three.module;
    if (!entry || !THREE) return JSON.stringify({failure: 'three.js not found'});
    const {renderer, scene, camera} = entry;
    const gl = renderer.getContext();
    const index = contextIndex.get(gl);
    const state = depthStates[index];
    const canvas = renderer.domElement;
    const width = gl.drawingBufferWidth, height = gl.drawingBufferHeight;
    // A page's pointer handler: NDC from CSS pixels over the canvas's CSS size; the buffer's
    // pixel (x, y) centre is at ((x + 0.5) / width, (y + 0.5) / height) of that size.
    const cssWidth = canvas.clientWidth || width / window.devicePixelRatio;
    const cssHeight = canvas.clientHeight || height / window.devicePixelRatio;
    const raycaster = new THREE.Raycaster();
    const objects = [];
    const objectIndex = new Map();
    const cast = (x, y) => {
      const cssX = x * cssWidth / width, cssY = y * cssHeight / height;
      raycaster.setFromCamera({x: cssX / cssWidth * 2 - 1, y: -(cssY / cssHeight) * 2 + 1}, camera);
      const hits = raycaster.intersectObject(scene, true);
      return hits.length ? hits[0] : null;
    };
    const normalMatrix = new THREE.Matrix3();
    const step = Math.pow(2, -state.subpixelBits);
    const picks = [];
    for (let row = 0; row < rows; ++row) {
      for (let column = 0; column < columns; ++column) {
        const x = Math.floor((column + 0.5) * width / columns);
        const y = Math.floor((row + 0.5) * height / rows);
        const hit = cast(x + 0.5, y + 0.5);
        const object = hit ? hit.object : null;
        let ambiguous = false;
        for (const [dx, dy] of [[-step, 0], [step, 0], [0, -step], [0, step]]) {
          const near = cast(x + 0.5 + dx, y + 0.5 + dy);
          if ((near ? near.object : null) !== object) ambiguous = true;
        }
        let reading = null;
        if (hit) {
          if (!objectIndex.has(object)) {
            objectIndex.set(object, objects.length);
            objects.push(object.name || (object.type + ' ' + object.id));
          }
          const normal = hit.face ? hit.face.normal.clone() : new THREE.Vector3();
          normal.applyMatrix3(normalMatrix.getNormalMatrix(object.matrixWorld)).normalize();
          reading = [hit.point.x, hit.point.y, hit.point.z, normal.x, normal.y, normal.z,
                     objectIndex.get(object)];
        }
        picks.push([x, y, reading, ambiguous]);
      }
    }
    const depthBuffer = renderer.state && renderer.state.buffers && renderer.state.buffers.depth;
    const reversedDepthBuffer = !!(depthBuffer && depthBuffer.getReversed &&
                                   depthBuffer.getReversed());
    // What the toggled run needs (PageToggle.hpp): three.js's reversed depth (r169 and later:
    // the depth buffer's setReversed), EXT_clip_control on the page's context, and no
    // logarithmic depth buffer (three.js turns that off under reversed depth).
    const hasExtension = (name) => {
      try {
        return !!(renderer.extensions && renderer.extensions.has(name));
      } catch (error) {
        return false;
      }
    };
    const toggle = {
      setReversed: !!(depthBuffer && typeof depthBuffer.setReversed === 'function'),
      clipControl: hasExtension('EXT_clip_control'),
      logarithmicDepthBuffer: !!(renderer.capabilities &&
                                 renderer.capabilities.logarithmicDepthBuffer),
      toggled: three.toggles,
    };
    const {clipDepth, clearDepth, depthRange, subpixelBits} = state;
    // The last thing done on the page: readDepth changes bindings behind three.js's state cache
    // (renderer.resetState would also turn its reversed depth off), and no frame is read after.
    const depth = readDepth(gl);
    return JSON.stringify({
      revision: THREE.REVISION || three.revision,
      canvas: rec.contexts[index].name, context: index, width, height, cssWidth, cssHeight,
      devicePixelRatio: window.devicePixelRatio,
      camera: {type: camera.type, orthographic: !!camera.isOrthographicCamera,
               near: camera.near, far: camera.far,
               projection: Array.from(camera.projectionMatrix.elements),
               view: Array.from(camera.matrixWorldInverse.elements)},
      reversedDepthBuffer, toggle, clipDepth, clearDepth, depthRange, subpixelBits, objects, picks,
      depth,
    });
  };
  rec.threeProgress = () => three.renderers.length + ' ' + three.scenes + ' ' + three.revision;

  rec.progress = () => rec.frames + ' ' + rec.draws + ' ' + rec.contexts.length + ' ' + rec.done;
  rec.snapshot = () => {
    // The canvas as it is now: its buffer's size, its size on the page, the pixel ratio.
    canvases.forEach(({canvas, gl}, index) => {
      Object.assign(rec.contexts[index], {
        canvasWidth: canvas.width, canvasHeight: canvas.height,
        clientWidth: canvas.clientWidth, clientHeight: canvas.clientHeight,
        drawingBufferWidth: gl.drawingBufferWidth, drawingBufferHeight: gl.drawingBufferHeight,
      });
    });
    return JSON.stringify({
      url: String(location.href), devicePixelRatio: window.devicePixelRatio, frames: rec.frames,
      draws: rec.draws, dropped: rec.dropped, contexts: rec.contexts, errors: rec.errors,
      pageErrors: rec.pageErrors,
      calls: rec.calls,
    });
  };
})
)js";

}  // namespace

std::string pageRecorderScript(std::uint64_t frames, bool verify, bool three,
                               bool toggleReversedDepth) {
  std::string script(kScript);
  script += "(";
  script += std::to_string(frames);
  script += verify ? ", true" : ", false";
  script += three ? ", true" : ", false";
  script += toggleReversedDepth ? ", true" : ", false";
  script += ");\n";
  return script;
}

}  // namespace clipray::page
