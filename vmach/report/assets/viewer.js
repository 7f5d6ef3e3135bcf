// report.html's interactive 3-D view (three.js, bundled into the page): the cut part coloured
// by deviation, the tool path (rapids red, feeds green) and the findings' places with their
// line numbers; an axis triad and a scale bar. Orthographic camera, Z up (the machine's).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';

// report.html#view: the 3-D view alone, filling the window
if (location.hash === '#view') document.body.classList.add('view-only');
const S = JSON.parse(document.getElementById('scene-data').textContent);
const box = document.getElementById('viewer');
const canvas = box.querySelector('canvas');

function decode(b64, Type) {
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}

const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0xffffff, 1);
renderer.autoClear = false;
const scene = new THREE.Scene();
const camera = new THREE.OrthographicCamera(-1, 1, 1, -1, -1e5, 1e5);
camera.up.set(0, 0, 1);
scene.add(new THREE.AmbientLight(0xffffff, 1.1));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
camera.add(sun); sun.position.set(0.4, 0.6, 1);
scene.add(camera);

const bounds = new THREE.Box3();
const layers = {};
if (S.part) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(decode(S.part.positions, Float32Array), 3));
  g.setAttribute('color', new THREE.BufferAttribute(decode(S.part.colours, Uint8Array), 3, true));
  g.setIndex(new THREE.BufferAttribute(decode(S.part.indices, Uint32Array), 1));
  g.computeVertexNormals();
  const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide, flatShading: true,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
  scene.add(m); layers.part = m;
  g.computeBoundingBox(); bounds.union(g.boundingBox);
}
if (S.path && S.path.segments > 0) {
  const p = decode(S.path.points, Float32Array), k = decode(S.path.kinds, Uint8Array);
  for (const [kind, colour, name] of [[0, 0xd62728, 'rapid'], [1, 0x2ca02c, 'feed']]) {
    const sel = [];
    for (let i = 0; i < k.length; i++) if (k[i] === kind) for (let j = 0; j < 6; j++) sel.push(p[6 * i + j]);
    if (!sel.length) continue;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(sel), 3));
    const l = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: colour }));
    scene.add(l); layers[name] = l;
    if (!S.part) { g.computeBoundingBox(); bounds.union(g.boundingBox); }
  }
}
const places = [];
const dot = new THREE.SphereGeometry(1, 12, 8);
for (const pl of S.places) {
  const at = new THREE.Vector3(...pl.at);
  const colour = { error: 0xd62728, warning: 0xff7f0e, info: 0x1f77b4 }[pl.severity] || 0x555555;
  const m = new THREE.Mesh(dot, new THREE.MeshBasicMaterial({ color: colour }));
  m.position.copy(at); scene.add(m);
  const el = document.createElement('div');
  el.className = 'label'; el.textContent = pl.label; el.style.color = '#' + colour.toString(16).padStart(6, '0');
  el.title = `${pl.kind} (${pl.severity})`; el.dataset.index = pl.index;
  el.addEventListener('click', () => window.vmachSelectFinding && window.vmachSelectFinding(pl.index));
  box.appendChild(el);
  places.push({ at, el, mesh: m });
  bounds.expandByPoint(at);
}
if (bounds.isEmpty()) bounds.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));

// axis triad: a small second scene drawn in the lower left corner, turned with the camera
const triScene = new THREE.Scene();
const triCam = new THREE.OrthographicCamera(-1.6, 1.6, 1.6, -1.6, -10, 10);
triCam.up.set(0, 0, 1);
triScene.add(new THREE.AxesHelper(1.1));
const axisLabels = ['X', 'Y', 'Z'].map((t, i) => {
  const el = document.createElement('div');
  el.className = 'axis'; el.textContent = t; el.style.color = ['#e00', '#0a0', '#00e'][i];
  box.appendChild(el); return el;
});
const scaleEl = document.createElement('div');
scaleEl.className = 'scalebar';
scaleEl.innerHTML = `<div></div><span>${S.scale_mm} mm</span>`;
box.appendChild(scaleEl);

const controls = new OrbitControls(camera, canvas);
const centre = bounds.getCenter(new THREE.Vector3());
const size = bounds.getSize(new THREE.Vector3()).length() || 1;
for (const p of places) p.mesh.scale.setScalar(size / 150);   // dots a fixed share of the view
function home() {
  controls.target.copy(centre);
  camera.position.copy(centre).add(new THREE.Vector3(1, -1.2, 0.9).normalize().multiplyScalar(size * 2));
  camera.zoom = 1; fit(); controls.update();
}
function fit() {
  const w = box.clientWidth, h = box.clientHeight, a = w / h, r = size * 0.62;
  camera.left = -r * a; camera.right = r * a; camera.top = r; camera.bottom = -r;
  camera.updateProjectionMatrix();
  renderer.setSize(w, h, false);
}

function draw() {
  const w = box.clientWidth, h = box.clientHeight;
  renderer.setViewport(0, 0, w, h); renderer.setScissorTest(false); renderer.clear();
  renderer.render(scene, camera);
  const v = new THREE.Vector3();
  for (const p of places) {
    v.copy(p.at).project(camera);
    const vis = p.mesh.visible && Math.abs(v.x) <= 1 && Math.abs(v.y) <= 1;
    p.el.style.display = vis ? '' : 'none';
    p.el.style.left = `${(v.x + 1) / 2 * w}px`; p.el.style.top = `${(1 - v.y) / 2 * h}px`;
  }
  const t = 110;  // the triad's square, px
  triCam.position.copy(camera.position).sub(controls.target).normalize().multiplyScalar(3);
  triCam.lookAt(0, 0, 0);
  renderer.setViewport(0, 0, t, t); renderer.setScissor(0, 0, t, t); renderer.setScissorTest(true);
  renderer.clearDepth(); renderer.render(triScene, triCam);
  ['x', 'y', 'z'].forEach((c, i) => {
    v.set(i === 0 ? 1.4 : 0, i === 1 ? 1.4 : 0, i === 2 ? 1.4 : 0).project(triCam);
    axisLabels[i].style.left = `${(v.x + 1) / 2 * t}px`; axisLabels[i].style.top = `${h - (v.y + 1) / 2 * t}px`;
  });
  const px = S.scale_mm * camera.zoom * h / (camera.top - camera.bottom);
  scaleEl.firstChild.style.width = `${px}px`;
}
controls.addEventListener('change', draw);
window.addEventListener('resize', () => { fit(); draw(); });
for (const input of document.querySelectorAll('.controls input[data-layer]')) {
  input.addEventListener('change', () => {
    const name = input.dataset.layer;
    if (name === 'places') places.forEach(p => { p.mesh.visible = input.checked; });
    else if (layers[name]) layers[name].visible = input.checked;
    draw();
  });
}
document.getElementById('view-home')?.addEventListener('click', () => { home(); draw(); });
window.vmachFocus = (index) => {
  const p = places.find(q => Number(q.el.dataset.index) === index);
  if (!p) return false;
  controls.target.copy(p.at); camera.zoom = 4; camera.updateProjectionMatrix(); controls.update(); draw();
  return true;
};
home(); draw();

// the page says what it drew (for a reader's tools and the browser test)
const gl = renderer.getContext();
const px = new Uint8Array(4 * 64 * 64);
let inked = 0;
const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
for (let gy = 0; gy < 8; gy++) for (let gx = 0; gx < 8; gx++) {
  gl.readPixels(Math.floor((gx + 0.5) * w / 8) - 4, Math.floor((gy + 0.5) * h / 8) - 4, 8, 8, gl.RGBA, gl.UNSIGNED_BYTE, px);
  for (let i = 0; i < 64 * 4; i += 4) if (px[i] < 245 || px[i + 1] < 245 || px[i + 2] < 245) inked++;
}
box.dataset.drawn = String(S.part ? S.part.triangles : 0);
box.dataset.inked = String(inked);
