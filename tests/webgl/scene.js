// The scene every test page draws (tests/webgl/*.html): two triangles at different depths seen
// through one world-to-clip matrix, uploaded as the uniform clipFromWorld, drawn every animation
// frame: drawScene(canvas, options); a page that sets window.PAGE before loading this has it drawn
// on its canvas#view. The options:
//   projection: 'no' (GL's [-1, 1] depth), 'zo' ([0, 1]) or 'zo-reversed' (near at 1, far at 0)
//   clipControl: true to call EXT_clip_control's clipControlEXT(LOWER_LEFT, ZERO_TO_ONE)
//   depthFunc: 'LESS', 'GREATER', ...; clearDepth: the depth clear value
//   near, far: the projection's planes
//   ubo: true to keep clipFromWorld in a std140 uniform block Camera (bufferSubData each frame)
//   webgl1: true for a WebGL 1 context (GLSL ES 1.00)
'use strict';
window.drawScene = (canvas, page) => {
  const gl = canvas.getContext(page.webgl1 ? 'webgl' : 'webgl2');
  if (!gl) throw new Error('no WebGL');
  if (page.clipControl) {
    const ext = gl.getExtension('EXT_clip_control');
    if (!ext) throw new Error('no EXT_clip_control');
    ext.clipControlEXT(ext.LOWER_LEFT_EXT, ext.ZERO_TO_ONE_EXT);
  }

  // Column-major 4x4 matrices (as uniformMatrix4fv takes them with transpose false).
  const multiply = (a, b) => {
    const out = new Array(16).fill(0);
    for (let c = 0; c < 4; ++c) {
      for (let r = 0; r < 4; ++r) {
        for (let k = 0; k < 4; ++k) out[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
      }
    }
    return out;
  };
  const perspective = (fovY, aspect, near, far, depth) => {
    const f = 1 / Math.tan(fovY / 2);
    const m = [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0];
    if (depth === 'no') {  // glm::perspectiveRH_NO
      m[10] = -(far + near) / (far - near);
      m[14] = -2 * far * near / (far - near);
    } else if (depth === 'zo') {  // glm::perspectiveRH_ZO
      m[10] = far / (near - far);
      m[14] = -far * near / (far - near);
    } else {  // zo-reversed: near -> 1, far -> 0
      m[10] = near / (far - near);
      m[14] = far * near / (far - near);
    }
    return m;
  };
  const lookAt = (eye, center, up) => {  // glm::lookAtRH
    const sub = (a, b) => a.map((v, i) => v - b[i]);
    const norm = (a) => { const l = Math.hypot(...a); return a.map((v) => v / l); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                             a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const f = norm(sub(center, eye));
    const s = norm(cross(f, up));
    const u = cross(s, f);
    return [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
            -dot(s, eye), -dot(u, eye), dot(f, eye), 1];
  };

  const compile = (type, source) => {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
    return shader;
  };
  const program = gl.createProgram();
  if (page.webgl1) {
    gl.attachShader(program, compile(gl.VERTEX_SHADER, `
      uniform mat4 clipFromWorld;
      attribute vec3 position;
      void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }`));
    gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `
      precision highp float;
      uniform vec3 color;
      void main() { gl_FragColor = vec4(color, 1.0); }`));
  } else {
    gl.attachShader(program, compile(gl.VERTEX_SHADER, `#version 300 es
      ${page.ubo ? 'layout(std140) uniform Camera { mat4 clipFromWorld; };'
                 : 'uniform mat4 clipFromWorld;'}
      in vec3 position;
      void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }`));
    gl.attachShader(program, compile(gl.FRAGMENT_SHADER, `#version 300 es
      precision highp float;
      uniform vec3 color;
      out vec4 fragColor;
      void main() { fragColor = vec4(color, 1.0); }`));
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const clipFromWorld = page.ubo ? null : gl.getUniformLocation(program, 'clipFromWorld');
  const camera = page.ubo ? gl.createBuffer() : null;
  if (page.ubo) {
    gl.uniformBlockBinding(program, gl.getUniformBlockIndex(program, 'Camera'), 0);
    gl.bindBuffer(gl.UNIFORM_BUFFER, camera);
    gl.bufferData(gl.UNIFORM_BUFFER, 64, gl.DYNAMIC_DRAW);
    gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, camera);
  }
  const color = gl.getUniformLocation(program, 'color');

  // A large far triangle at z = -2 and a small near one at z = 1.
  const vertices = new Float32Array([-3, -2, -2, 3, -2, -2, 0, 3, -2, -1, -1, 1, 1, -1, 1, 0, 1, 1]);
  const buffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, vertices, gl.STATIC_DRAW);
  const position = gl.getAttribLocation(program, 'position');
  gl.enableVertexAttribArray(position);
  gl.vertexAttribPointer(position, 3, gl.FLOAT, false, 0, 0);

  const matrix = multiply(perspective(Math.PI / 3, canvas.width / canvas.height, page.near,
                                      page.far, page.projection),
                          lookAt([0, 2, 5], [0, 0, 0], [0, 1, 0]));
  gl.enable(gl.DEPTH_TEST);
  gl.depthFunc(gl[page.depthFunc]);
  gl.clearDepth(page.clearDepth);
  gl.viewport(0, 0, canvas.width, canvas.height);
  const frame = () => {
    gl.clearColor(0.1, 0.1, 0.1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(program);
    if (page.ubo) {
      gl.bindBuffer(gl.UNIFORM_BUFFER, camera);
      gl.bufferSubData(gl.UNIFORM_BUFFER, 0, new Float32Array(matrix));
    } else {
      gl.uniformMatrix4fv(clipFromWorld, false, new Float32Array(matrix));
    }
    gl.uniform3f(color, 0.2, 0.4, 0.9);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.uniform3f(color, 0.9, 0.5, 0.1);
    gl.drawArrays(gl.TRIANGLES, 3, 3);
    requestAnimationFrame(frame);
  };
  requestAnimationFrame(frame);
};
if (window.PAGE) window.drawScene(document.getElementById('view'), window.PAGE);
