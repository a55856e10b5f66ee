// viewer.js: walk through ltm's baked global illumination (`ltm bake-gi`, docs/formats.md "Baked GI").
// The page holds one or two bakes (window.LTM_BAKES: [{name, glb}], glb as base64, so the folder
// opens from file:// without a server): the first is shown alone, or beside the second (e.g. the
// model's bake beside the path tracer's) with one shared camera. Each vertex's linear radiance
// (_RADIANCE) or indirect irradiance (_IRRADIANCE_INDIRECT) is tone-mapped in the shader exactly as
// the file's COLOR_0 is: Reinhard x / (1 + x) of exposure × value, then sRGB.
//
// Controls: drag to orbit, wheel to zoom, W A S D (and Q E) to walk, the scene's cameras as
// bookmarks. URL hash: #camera=N&exposure=X&mode=radiance|irradiance (the browser test opens a camera).
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const vertexShader = `
attribute vec3 _radiance;
attribute vec3 _irradiance_indirect;
uniform float mode;
varying vec3 vValue;
void main() {
  // E+ is shown as the radiance a white (rho = 1) diffuse surface would send: E+ / pi.
  vValue = mode < 0.5 ? _radiance : _irradiance_indirect / 3.14159265;
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const fragmentShader = `
uniform float exposure;
varying vec3 vValue;
float srgb(float c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055; }
void main() {
  vec3 x = max(vValue * exposure, vec3(0.0));
  vec3 t = x / (1.0 + x);
  gl_FragColor = vec4(srgb(t.r), srgb(t.g), srgb(t.b), 1.0);
}`;

function decodeBase64(text) {
  const bin = atob(text);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return bytes.buffer;
}

function parseHash() {
  const out = {};
  for (const part of window.location.hash.replace(/^#/, '').split('&')) {
    const [k, v] = part.split('=');
    if (k) out[k] = decodeURIComponent(v || '');
  }
  return out;
}

async function loadBake(bake, uniforms) {
  const gltf = await new GLTFLoader().parseAsync(decodeBase64(bake.glb), '');
  const material = new THREE.ShaderMaterial({ vertexShader, fragmentShader, uniforms, side: THREE.FrontSide });
  gltf.scene.traverse((o) => {
    if (o.isMesh) o.material = material;
  });
  return gltf;
}

async function main() {
  const hash = parseHash();
  const bakes = window.LTM_BAKES || [];
  if (bakes.length === 0) throw new Error('no bake in this page (window.LTM_BAKES is empty)');
  const uniforms = {
    exposure: { value: hash.exposure ? parseFloat(hash.exposure) : 1.0 },
    mode: { value: hash.mode === 'irradiance' ? 1.0 : 0.0 },
  };
  const loaded = [];
  for (const b of bakes) loaded.push(await loadBake(b, uniforms));

  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;   // the shader writes sRGB itself
  document.getElementById('view').appendChild(renderer.domElement);
  const camera = new THREE.PerspectiveCamera(60, 1, 0.01, 1000);

  // Bookmarks: the first bake's cameras (world matrices from their nodes).
  const bookmarks = [];
  loaded[0].scene.updateMatrixWorld(true);
  for (const c of loaded[0].cameras) {
    const pos = new THREE.Vector3(), quat = new THREE.Quaternion(), scale = new THREE.Vector3();
    c.matrixWorld.decompose(pos, quat, scale);
    bookmarks.push({ name: c.name || `camera ${bookmarks.length}`, fov: c.fov, pos, quat });
  }
  const box = new THREE.Box3().setFromObject(loaded[0].scene);
  const extent = box.getSize(new THREE.Vector3()).length();
  camera.near = 1e-3 * extent;
  camera.far = 10 * extent;
  const controls = new OrbitControls(camera, renderer.domElement);

  function goTo(b) {
    camera.position.copy(b.pos);
    camera.quaternion.copy(b.quat);
    camera.fov = b.fov;
    const forward = new THREE.Vector3(0, 0, -1).applyQuaternion(b.quat);
    controls.target.copy(b.pos).addScaledVector(forward, 0.25 * extent);
    camera.updateProjectionMatrix();
    controls.update();
  }
  if (bookmarks.length > 0) goTo(bookmarks[Math.min(bookmarks.length - 1, parseInt(hash.camera || '0', 10))]);
  else {
    camera.position.copy(box.getCenter(new THREE.Vector3())).add(new THREE.Vector3(0, 0, extent));
    controls.target.copy(box.getCenter(new THREE.Vector3()));
    controls.update();
  }

  // The panel: bookmarks, exposure, what is shown.
  const panel = document.getElementById('panel');
  if (panel) {
    for (const b of bookmarks) {
      const button = document.createElement('button');
      button.textContent = b.name;
      button.onclick = () => goTo(b);
      panel.appendChild(button);
    }
    const exposure = document.getElementById('exposure');
    exposure.value = Math.log2(uniforms.exposure.value);
    exposure.oninput = () => (uniforms.exposure.value = Math.pow(2, parseFloat(exposure.value)));
    const mode = document.getElementById('mode');
    mode.value = uniforms.mode.value > 0.5 ? 'irradiance' : 'radiance';
    mode.onchange = () => (uniforms.mode.value = mode.value === 'irradiance' ? 1 : 0);
    document.getElementById('names').textContent = bakes.map((b) => b.name).join('  |  ');
  }

  // Walking: W/S along the view, A/D sideways, Q/E down/up; the orbit target moves along.
  const keys = new Set();
  window.addEventListener('keydown', (e) => keys.add(e.key.toLowerCase()));
  window.addEventListener('keyup', (e) => keys.delete(e.key.toLowerCase()));
  const clock = new THREE.Clock();
  function walk() {
    const dt = Math.min(clock.getDelta(), 0.1), speed = 0.15 * extent * dt;
    const forward = new THREE.Vector3();
    camera.getWorldDirection(forward);
    const side = new THREE.Vector3().crossVectors(forward, camera.up).normalize();
    const move = new THREE.Vector3();
    if (keys.has('w')) move.add(forward);
    if (keys.has('s')) move.sub(forward);
    if (keys.has('d')) move.add(side);
    if (keys.has('a')) move.sub(side);
    if (keys.has('e')) move.add(camera.up);
    if (keys.has('q')) move.sub(camera.up);
    if (move.lengthSq() > 0) {
      move.normalize().multiplyScalar(speed);
      camera.position.add(move);
      controls.target.add(move);
    }
  }

  function frame() {
    frame_once();
    window.LTM_FRAMES = (window.LTM_FRAMES || 0) + 1;
    requestAnimationFrame(frame);
  }
  function frame_once() {
    walk();
    controls.update();
    const w = window.innerWidth, h = window.innerHeight;
    renderer.setSize(w, h, false);
    renderer.domElement.style.width = `${w}px`;
    renderer.domElement.style.height = `${h}px`;
    renderer.setScissorTest(true);
    const n = loaded.length, vw = Math.floor(w / n);
    camera.aspect = vw / h;
    camera.updateProjectionMatrix();
    for (let i = 0; i < n; ++i) {
      renderer.setViewport(i * vw, 0, vw, h);
      renderer.setScissor(i * vw, 0, vw, h);
      renderer.render(loaded[i].scene, camera);
    }
  }
  if (hash.bench) {
    // #bench=N: N frames drawn back to back (a 1-pixel read forces each to finish); the mean time
    // per frame goes into the title (`chromium --dump-dom` reads it: scripts/viewer-fps.sh).
    const n = parseInt(hash.bench, 10), px = new Uint8Array(4), gl = renderer.getContext();
    frame_once();
    const t0 = performance.now();
    for (let i = 0; i < n; ++i) {
      frame_once();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    }
    const ms = (performance.now() - t0) / n;
    let vertices = 0;
    for (const l of loaded) l.scene.traverse((o) => { if (o.isMesh) vertices += o.geometry.attributes.position.count; });
    document.title = `ltm-bench ms_per_frame=${ms.toFixed(2)} fps=${(1000 / ms).toFixed(1)} vertices=${vertices} size=${window.innerWidth}x${window.innerHeight}`;
  }
  frame();
  window.LTM_READY = true;
}

main().catch((e) => {
  document.body.textContent = `ltm viewer: ${e.message}`;
  window.LTM_ERROR = e.message;
});
