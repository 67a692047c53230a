// The scene every three.js test page draws (tests/webgl/three/*.html), with three.js from npm
// (package.json pins it; harness/install-deps.sh runs `npm ci` here): three boxes and a ground
// plane at different depths, 320x240, rendered every animation frame, seen by a perspective
// (fov 60, near 0.1, far 100) or an orthographic (12 x 9 units, near 0.1, far 100) camera at
// (0, 4, 10) looking at the origin. The page sets window.PAGE before importing this module:
//   camera: 'perspective' or 'orthographic'
//   reversedDepthBuffer: true for WebGLRenderer({reversedDepthBuffer: true}) (EXT_clip_control)
//   material: 'basic' (MeshBasicMaterial) or 'shader' (a ShaderMaterial of the page's own)
//   doubleSided: true for THREE.DoubleSide materials
//   mistake: one of the classic ones, each described where it is made below.
import * as THREE from 'three';

const page = window.PAGE || {};
const canvas = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({
  canvas,
  antialias: false,
  reversedDepthBuffer: page.reversedDepthBuffer === true,
});
renderer.setPixelRatio(1);
renderer.setSize(canvas.width, canvas.height, false);
renderer.setClearColor(0x202020);

const aspect = canvas.width / canvas.height;
const camera = page.camera === 'orthographic'
                   ? new THREE.OrthographicCamera(-6, 6, 4.5, -4.5, 0.1, 100)
                   : new THREE.PerspectiveCamera(60, aspect, 0.1, 100);
camera.position.set(0, 4, 10);
camera.lookAt(0, 0, 0);
camera.updateMatrixWorld();

if (page.mistake === 'reversed-camera') {
  // (a) A reversed-Z camera on a renderer that does not know it: the projection is built
  // reversed (near at 1, far at 0) by hand, but the renderer keeps its default depth state
  // (LEQUAL, cleared to 1) and the page's ShaderMaterial the default depthFunc: where surfaces
  // overlap the farther one wins.
  camera.projectionMatrix.makePerspective(
      -0.1 * Math.tan(Math.PI / 6) * aspect, 0.1 * Math.tan(Math.PI / 6) * aspect,
      0.1 * Math.tan(Math.PI / 6), -0.1 * Math.tan(Math.PI / 6), 0.1, 100,
      THREE.WebGLCoordinateSystem, true);
  camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
  camera.updateProjectionMatrix = () => {};
}

if (page.mistake === 'orthographic-raycast') {
  // (b) The orthographic picking ray of three.js before reversed depth (r168's
  // Raycaster.setFromCamera), kept by a page that carries its own copy: the ray's origin is put
  // at z_ndc = (near + far) / (near - far), the camera's plane under [-1, 1] depth only. Under
  // reversed depth that z_ndc unprojects to beyond the far plane, and the ray, cast away from
  // the camera, misses everything.
  THREE.Raycaster.prototype.setFromCamera = function(coords, cam) {
    if (cam.isOrthographicCamera) {
      this.ray.origin.set(coords.x, coords.y, (cam.near + cam.far) / (cam.near - cam.far))
          .unproject(cam);
      this.ray.direction.set(0, 0, -1).transformDirection(cam.matrixWorld);
      this.camera = cam;
    } else {
      this.ray.origin.setFromMatrixPosition(cam.matrixWorld);
      this.ray.direction.set(coords.x, coords.y, 0.5).unproject(cam).sub(this.ray.origin)
          .normalize();
      this.camera = cam;
    }
  };
}

if (page.mistake === 'depth-picker') {
  // (c) A picker written for GL's [-1, 1] depth: the pick ray runs from the unprojection of
  // z_ndc = -1 (the near plane under [-1, 1]) to that of z_ndc = 1 (the far plane), as
  // gluUnProject at window depths 0 and 1 gives. Under EXT_clip_control's ZERO_TO_ONE with
  // reversed depth, 1 is the near plane and -1 lies 2 far - near beyond it: from an orthographic
  // camera the ray starts behind the far plane and runs toward the camera, and its first hit is
  // the farthest surface (the page's materials are double-sided, so the ray sees back faces).
  THREE.Raycaster.prototype.setFromCamera = function(coords, cam) {
    const near = new THREE.Vector3(coords.x, coords.y, -1).unproject(cam);
    const far = new THREE.Vector3(coords.x, coords.y, 1).unproject(cam);
    this.ray.origin.copy(near);
    this.ray.direction.copy(far).sub(near).normalize();
    this.camera = cam;
  };
}

const material = (color) => {
  const side = page.doubleSided ? THREE.DoubleSide : THREE.FrontSide;
  if (page.material !== 'shader') return new THREE.MeshBasicMaterial({color, side});
  return new THREE.ShaderMaterial({
    side,
    uniforms: {color: {value: new THREE.Color(color)}},
    vertexShader: `void main() {
      gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
    }`,
    fragmentShader: `uniform vec3 color;
    void main() { gl_FragColor = vec4(color, 1.0); }`,
  });
};

const scene = new THREE.Scene();
const ground = new THREE.Mesh(new THREE.PlaneGeometry(20, 20), material(0x606060));
ground.rotation.x = -Math.PI / 2;
scene.add(ground);
const boxes = [[-2.5, 1, 0, 0xc04040], [0, 1, -3, 0x40c040], [2.5, 1, 2, 0x4040c0]];
for (const [x, y, z, color] of boxes) {
  const box = new THREE.Mesh(new THREE.BoxGeometry(2, 2, 2), material(color));
  box.position.set(x, y, z);
  box.rotation.y = 0.5;
  scene.add(box);
}
// A box in front of the green one, overlapping it on screen (where the mistake of (a) shows).
const front = new THREE.Mesh(new THREE.BoxGeometry(1, 1, 1), material(0xc0c040));
front.position.set(0, 2.5, 1);
scene.add(front);

renderer.setAnimationLoop(() => renderer.render(scene, camera));
