// symdyn's HTML viewer: the glTF animation written by the runtime (gltf.hpp),
// its clips (the motion, then each mode), and the time histories plotted
// beside it with a cursor at the current time. Everything it shows comes from
// the JSON in <script id="symdyn-data">: { title, glb (base64), series:
// { names, columns } }. The URL's hash sets the start: #t=1.5&clip=0&paused.
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const css = `
body { margin: 0; font: 13px system-ui, sans-serif; display: flex; height: 100vh; background: #f4f4f6; }
#view { flex: 3; position: relative; min-width: 0; }
#view canvas { display: block; }
#bar { position: absolute; left: 8px; right: 8px; bottom: 8px; display: flex; gap: 8px; align-items: center;
       background: #ffffffd0; padding: 6px 8px; border-radius: 6px; }
#bar input[type=range] { flex: 1; }
#bar span { min-width: 7em; white-space: nowrap; }
#bar select { max-width: 16em; }
#title { position: absolute; left: 10px; top: 8px; font-weight: 600; }
#hover { position: absolute; pointer-events: none; background: #222; color: #fff; padding: 2px 6px;
         border-radius: 4px; display: none; }
#side { flex: 2; display: flex; flex-direction: column; border-left: 1px solid #ccc; background: #fff; min-width: 0; }
#series { padding: 6px 8px; overflow-y: auto; max-height: 30%; columns: 3; }
#series label { display: block; white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
#plot { flex: 1; min-height: 0; }
`;

const palette = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf'];

function element(tag, attributes = {}, parent = null) {
  const e = Object.assign(document.createElement(tag), attributes);
  if (parent) parent.appendChild(e);
  return e;
}

function decodeBase64(text) {
  const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
  return bytes.buffer;
}

function hashOptions() {
  const options = {};
  for (const part of location.hash.replace(/^#/, '').split('&')) {
    if (!part) continue;
    const [key, value] = part.split('=');
    options[key] = value === undefined ? true : value;
  }
  return options;
}

// The bodies are the children of the root node "world"; a mesh under the mouse
// is named by the body it belongs to.
function bodyOf(object) {
  while (object.parent && object.parent.name !== 'world') object = object.parent;
  return object.parent ? object.name : null;
}

// A line plot of the chosen series against time, with a cursor.
class Plot {
  constructor(canvas, series) {
    this.canvas = canvas;
    this.names = series.names;
    this.columns = series.columns;
    this.chosen = new Set(this.names.slice(1, 3));
    this.time = 0;
  }

  draw() {
    const c = this.canvas;
    const ratio = window.devicePixelRatio || 1;
    c.width = c.clientWidth * ratio;
    c.height = c.clientHeight * ratio;
    const g = c.getContext('2d');
    g.scale(ratio, ratio);
    const w = c.clientWidth, h = c.clientHeight, left = 56, right = 10, top = 10, bottom = 28;
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    const t = this.columns[0];
    if (!t || t.length === 0) return;
    const shown = this.names.map((n, i) => i).filter((i) => i > 0 && this.chosen.has(this.names[i]));
    let lo = Infinity, hi = -Infinity;
    for (const i of shown) for (const v of this.columns[i]) if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (!(hi > lo)) { lo = (isFinite(lo) ? lo : 0) - 1; hi = lo + 2; }
    const t0 = t[0], t1 = t[t.length - 1] > t0 ? t[t.length - 1] : t0 + 1;
    const x = (v) => left + ((v - t0) / (t1 - t0)) * (w - left - right);
    const y = (v) => top + ((hi - v) / (hi - lo)) * (h - top - bottom);
    g.strokeStyle = '#999';
    g.strokeRect(left, top, w - left - right, h - top - bottom);
    g.fillStyle = '#333';
    g.font = '11px system-ui, sans-serif';
    g.textAlign = 'right';
    g.fillText(hi.toPrecision(4), left - 4, top + 10);
    g.fillText(lo.toPrecision(4), left - 4, h - bottom);
    g.textAlign = 'left';
    g.fillText(`t = ${t0} … ${t1} s`, left, h - 8);
    shown.forEach((i, k) => {
      g.strokeStyle = palette[k % palette.length];
      g.beginPath();
      this.columns[i].forEach((v, j) => (j ? g.lineTo(x(t[j]), y(v)) : g.moveTo(x(t[j]), y(v))));
      g.stroke();
      g.fillStyle = g.strokeStyle;
      g.fillText(this.names[i], left + 6 + 90 * (k % 4), top + 14 + 14 * Math.floor(k / 4));
    });
    g.strokeStyle = '#000';
    g.beginPath();
    g.moveTo(x(t0 + this.time), top);
    g.lineTo(x(t0 + this.time), h - bottom);
    g.stroke();
  }
}

// The camera looks at the whole motion: the box the bodies sweep over the
// first clip (sampled), from above and aside.
function sweptBox(root, mixer, clip) {
  const box = new THREE.Box3().setFromObject(root);
  if (!clip) return box;
  const action = mixer.clipAction(clip);
  action.play();
  for (let k = 0; k <= 24; ++k) {
    action.time = (clip.duration * k) / 24;
    mixer.update(0);
    box.expandByObject(root);
  }
  action.stop();
  return box;
}

function frameCamera(camera, controls, box) {
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  const centre = box.getCenter(new THREE.Vector3());
  camera.near = size / 100;
  camera.far = size * 100;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.5, 1.0).normalize().multiplyScalar(size * 1.3));
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
}

async function main() {
  element('style', { textContent: css }, document.head);
  const data = JSON.parse(document.getElementById('symdyn-data').textContent);
  document.title = `${data.title} (symdyn)`;
  const view = element('div', { id: 'view' }, document.body);
  const side = element('div', { id: 'side' }, document.body);
  element('div', { id: 'title', textContent: data.title }, view);
  const hover = element('div', { id: 'hover' }, view);
  const bar = element('div', { id: 'bar' }, view);
  const play = element('button', { textContent: 'Pause' }, bar);
  const slider = element('input', { type: 'range', min: 0, max: 1, step: 'any', value: 0 }, bar);
  const clock = element('span', { textContent: 't = 0 s' }, bar);
  const speed = element('select', {}, bar);
  for (const s of [0.1, 0.25, 0.5, 1, 2, 4]) element('option', { value: s, textContent: `${s}×`, selected: s === 1 }, speed);
  const clipSelect = element('select', {}, bar);

  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f6);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x606070, 2.0));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(3, 5, 4);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
  const controls = new OrbitControls(camera, renderer.domElement);

  const gltf = await new GLTFLoader().parseAsync(decodeBase64(data.glb), '');
  scene.add(gltf.scene);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  const clips = gltf.animations;
  const box = sweptBox(gltf.scene, mixer, clips[0]);
  frameCamera(camera, controls, box);
  const grid = new THREE.GridHelper(box.getSize(new THREE.Vector3()).length() * 2, 20, 0x999999, 0xcccccc);
  grid.position.set(box.getCenter(new THREE.Vector3()).x, box.min.y, box.getCenter(new THREE.Vector3()).z);
  scene.add(grid);
  clips.forEach((clip, i) => element('option', { value: i, textContent: clip.name }, clipSelect));
  let action = null;
  function selectClip(i) {
    if (action) action.stop();
    if (!clips[i]) return;
    action = mixer.clipAction(clips[i]);
    action.play();
    slider.max = clips[i].duration || 1;
    clipSelect.value = i;
  }

  const series = data.series || { names: ['t'], columns: [[]] };
  const list = element('div', { id: 'series' }, side);
  const plot = new Plot(element('canvas', { id: 'plot' }, side), series);
  series.names.slice(1).forEach((name) => {
    const label = element('label', {}, list);
    const box = element('input', { type: 'checkbox', checked: plot.chosen.has(name) }, label);
    label.append(` ${name}`);
    box.onchange = () => { box.checked ? plot.chosen.add(name) : plot.chosen.delete(name); plot.draw(); };
  });

  const options = hashOptions();
  let paused = options.paused === true || options.t !== undefined;
  let time = Number(options.t) || 0;
  selectClip(Number(options.clip) || 0);
  play.textContent = paused ? 'Play' : 'Pause';
  play.onclick = () => { paused = !paused; play.textContent = paused ? 'Play' : 'Pause'; };
  slider.oninput = () => { time = Number(slider.value); };
  clipSelect.onchange = () => { selectClip(Number(clipSelect.value)); time = 0; };

  const pointer = new THREE.Vector2();
  const raycaster = new THREE.Raycaster();
  renderer.domElement.addEventListener('pointermove', (event) => {
    const r = renderer.domElement.getBoundingClientRect();
    pointer.set(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    const hit = raycaster.intersectObject(gltf.scene, true)[0];
    const name = hit && bodyOf(hit.object);
    hover.style.display = name ? 'block' : 'none';
    if (name) Object.assign(hover.style, { left: `${event.clientX - r.left + 12}px`, top: `${event.clientY - r.top + 12}px` });
    hover.textContent = name || '';
  });

  function resize() {
    const w = view.clientWidth, h = view.clientHeight;
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    plot.draw();
  }
  window.addEventListener('resize', resize);
  resize();

  function show(t) {
    const duration = action ? action.getClip().duration : 0;
    time = duration > 0 ? ((t % duration) + duration) % duration : 0;
    if (action) { action.time = time; mixer.update(0); }
    slider.value = time;
    clock.textContent = `t = ${time.toFixed(3)} s`;
    plot.time = clipSelect.value === '0' ? time : 0;
    plot.draw();
    renderer.render(scene, camera);
  }

  let last = performance.now();
  function frame(now) {
    const dt = (now - last) / 1000;
    last = now;
    if (!paused) time += dt * Number(speed.value);
    show(time);
    requestAnimationFrame(frame);
  }
  requestAnimationFrame(frame);
  document.body.dataset.ready = 'true';
  // For scripts and tests: the state of the viewer, and a way to move it.
  window.symdynViewer = { ready: true, clips: clips.map((c) => c.name), bodies: gltf.scene.children[0]?.children.map((c) => c.name) ?? [],
                          setTime: (t) => { paused = true; show(t); }, time: () => time };
}

main().catch((error) => {
  document.body.textContent = `symdyn viewer: ${error.message}`;
  document.body.dataset.error = error.message;
  window.symdynViewer = { ready: false, error: error.message };
});
