// symdyn's HTML viewer: the glTF animation written by the runtime (gltf.hpp),
// its clips (the motion, then each mode), and the time histories plotted
// beside it with a cursor at the current time (plot.js). Everything it shows
// comes from the JSON in <script id="symdyn-data">: { title, glb (base64),
// series: { names, columns, units }, arrows: { names, points, vectors } (forces
// drawn at points, optional) }. The camera frames the bodies and, for a
// motion that goes well beyond them, follows them (a toggle); the path is drawn
// on the ground. The URL's hash sets the start: #t=1.5&clip=0&paused&follow=0.
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { Plot } from './plot.js';
import { roundUp } from './axis.js';

const css = `
body { margin: 0; font: 13px system-ui, sans-serif; display: flex; height: 100vh; background: #f4f4f6; }
#view { flex: 3; position: relative; min-width: 0; }
#view canvas { display: block; }
#bar { position: absolute; left: 8px; right: 8px; bottom: 8px; display: flex; flex-wrap: wrap; gap: 8px; align-items: center;
       background: #ffffffd0; padding: 6px 8px; border-radius: 6px; }
#bar input[type=range] { flex: 1; min-width: 80px; }
#bar span { min-width: 7em; white-space: nowrap; }
#bar select { max-width: 11em; }
#title { position: absolute; left: 10px; top: 8px; font-weight: 600; }
#hover { position: absolute; pointer-events: none; background: #222; color: #fff; padding: 2px 6px;
         border-radius: 4px; display: none; }
#side { flex: 2; display: flex; flex-direction: column; border-left: 1px solid #ccc; background: #fff; min-width: 0; }
#series { padding: 6px 8px; overflow-y: auto; max-height: 30%; columns: 3; }
#series label { display: block; white-space: nowrap; overflow: hidden; text-overflow: ellipsis; }
#series .swatch { display: inline-block; width: 16px; margin: 0 5px 3px 2px; vertical-align: middle; }
#bar label { white-space: nowrap; }
#plot { flex: 1; min-height: 0; }
`;

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

// The bodies' box in the pose shown (precise: from the vertices, not from
// the turned boxes of the meshes).
function bodiesBox(root, precise = false) {
  return new THREE.Box3().setFromObject(root, precise);
}

// The mean of the bodies' origins (their centres of mass): what the camera
// follows and the path traces, steady while a wheel turns.
function bodiesCentre(root) {
  const bodies = root.children[0]?.children ?? [];
  const centre = new THREE.Vector3();
  for (const body of bodies) centre.add(body.getWorldPosition(new THREE.Vector3()));
  return bodies.length ? centre.divideScalar(bodies.length) : bodiesBox(root).getCenter(centre);
}

// The first clip sampled: the box the bodies sweep, and the path of their
// centre (drawn on the ground).
function sweep(root, mixer, clip, samples = 200) {
  const swept = bodiesBox(root, true), path = [bodiesCentre(root)];
  if (!clip) return { swept, path };
  const action = mixer.clipAction(clip);
  action.play();
  for (let k = 0; k <= samples; ++k) {
    action.time = (clip.duration * k) / samples;
    mixer.update(0);
    swept.union(bodiesBox(root, true));
    path.push(bodiesCentre(root));
  }
  action.stop();
  return { swept, path };
}

// A square floor of `cells` × `cells` cells of side `cell`, lined at their
// edges, in the y = 0 plane.
function groundGrid(cell, cells) {
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 64;
  const g = canvas.getContext('2d');
  g.fillStyle = '#efeff2';
  g.fillRect(0, 0, 64, 64);
  g.fillStyle = '#c8c8d0';
  g.fillRect(0, 0, 64, 2);
  g.fillRect(0, 0, 2, 64);
  const texture = new THREE.CanvasTexture(canvas);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.repeat.set(cells, cells);
  texture.anisotropy = 8;
  texture.colorSpace = THREE.SRGBColorSpace;
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(cell * cells, cell * cells),
    new THREE.MeshBasicMaterial({ map: texture, depthWrite: false }));
  plane.rotation.x = -Math.PI / 2;
  plane.renderOrder = -1;  // under the path and the bodies it touches
  return plane;
}

// The camera looks at the bodies (not their whole path) from above and aside.
function frameCamera(camera, controls, box) {
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  const centre = box.getCenter(new THREE.Vector3());
  camera.near = size / 200;
  camera.far = size * 500;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.5, 1.0).normalize().multiplyScalar(size * 1.6));
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
  const start = bodiesBox(gltf.scene, true);  // the first pose
  let centre = bodiesCentre(gltf.scene);
  const { swept, path } = sweep(gltf.scene, mixer, clips[0]);
  // The ground: a floor of round cells at the lowest point reached, moved in
  // whole cells under the camera's target so that it never ends. (A textured
  // plane, not lines: lines that pass behind the camera are dropped by some
  // renderers.)
  const bodySize = start.getSize(new THREE.Vector3()).length() || 1;
  const cell = roundUp(bodySize / 4), cells = 200, floor = swept.min.y;
  const grid = groundGrid(cell, cells);
  grid.position.y = floor;
  scene.add(grid);
  const placeGrid = () => grid.position.set(Math.round(controls.target.x / cell) * cell, floor,
    Math.round(controls.target.z / cell) * cell);
  // The path of the motion on the ground, seen from above.
  const trace = new THREE.Line(new THREE.BufferGeometry().setFromPoints(path.map((p) => new THREE.Vector3(p.x, floor + cell * 1e-3, p.z))),
    new THREE.LineBasicMaterial({ color: 0xe15759 }));
  scene.add(trace);
  // Following: the camera and its target move with the bodies' centre. On
  // when the motion goes well beyond the bodies (a vehicle), off for a
  // mechanism that stays in place; the hash's follow=0 or 1 decides.
  const followLabel = element('label', { title: 'the camera moves with the bodies' }, bar);
  const follow = element('input', { type: 'checkbox' }, followLabel);
  followLabel.append(' follow');
  const options = hashOptions();
  follow.checked = options.follow !== undefined ? options.follow !== '0'
    : swept.getSize(new THREE.Vector3()).length() > 2.5 * bodySize;
  // A mechanism in place is seen whole; a vehicle, close.
  frameCamera(camera, controls, follow.checked ? start : swept);
  placeGrid();
  controls.addEventListener('change', placeGrid);
  function track() {
    const now = bodiesCentre(gltf.scene);
    if (follow.checked) {
      const move = now.clone().sub(centre);
      camera.position.add(move);
      controls.target.add(move);
      controls.update();
      placeGrid();
    }
    centre = now;
  }
  clips.forEach((clip, i) => element('option', { value: i, textContent: clip.name }, clipSelect));
  let action = null;
  function selectClip(i) {
    if (action) action.stop();
    trace.visible = Number(i) === 0;
    if (!clips[i]) return;
    action = mixer.clipAction(clips[i]);
    action.play();
    slider.max = clips[i].duration || 1;
    clipSelect.value = i;
  }

  const series = data.series || { names: ['t'], columns: [[]] };
  const list = element('div', { id: 'series' }, side);
  const plot = new Plot(element('canvas', { id: 'plot' }, side), series);
  const swatches = new Map();
  // Each ticked series' line style beside its name.
  const showSwatches = () => {
    const styles = new Map(plot.shown().map((s) => [s.i, s]));
    swatches.forEach((swatch, i) => {
      const s = styles.get(i);
      swatch.style.borderTop = s ? `3px ${s.dash.length ? 'dashed' : 'solid'} ${s.colour}` : '3px solid transparent';
    });
  };
  series.names.forEach((name, i) => {
    if (i === 0) return;
    const unit = plot.units[i];
    const label = element('label', { title: unit ? `${name} (${unit})` : name }, list);
    const box = element('input', { type: 'checkbox', checked: plot.chosen.has(name) }, label);
    swatches.set(i, element('span', { className: 'swatch' }, label));
    label.append(unit ? `${name} (${unit})` : name);
    box.onchange = () => { box.checked ? plot.chosen.add(name) : plot.chosen.delete(name); showSwatches(); plot.draw(); };
  });
  showSwatches();

  // Arrows (the loops' reaction forces): arrow k at points[k], along vectors[k]
  // (3 per time of the series, model axes, turned as the bodies' "world"), at
  // the last output instant up to the time, scaled together: the longest a
  // fifth of the bodies' size.
  const arrows = data.arrows || { names: [], points: [], vectors: [] };
  const times = series.columns[0] || [];
  let longest = 0;
  for (const v of arrows.vectors) {
    for (let k = 0; k + 2 < v.length; k += 3) longest = Math.max(longest, Math.hypot(v[k], v[k + 1], v[k + 2]));
  }
  const arrowScale = longest > 0 ? bodySize / 5 / longest : 0;
  const arrowRoot = new THREE.Group();
  const world = gltf.scene.getObjectByName('world');
  if (world) arrowRoot.quaternion.copy(world.quaternion);
  scene.add(arrowRoot);
  const helpers = arrows.names.map((name) => {
    const a = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0xd62728);
    a.name = name;
    arrowRoot.add(a);
    return a;
  });
  function placeArrows(t, shown) {
    let lo = 0, hi = times.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid - 1;
    }
    helpers.forEach((a, k) => {
      const p = arrows.points[k], v = arrows.vectors[k], i = 3 * lo;
      const force = new THREE.Vector3(v[i], v[i + 1], v[i + 2]);
      const length = force.length() * arrowScale;
      a.visible = shown && length > 0;
      if (!a.visible) return;
      a.position.set(p[i], p[i + 1], p[i + 2]);
      a.setDirection(force.normalize());
      a.setLength(length, 0.25 * length, 0.12 * length);
    });
  }

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
    placeArrows(time, clipSelect.value === '0');
    document.body.dataset.arrows = String(helpers.filter((a) => a.visible).length);
    track();
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
                          setTime: (t) => { paused = true; show(t); }, time: () => time, following: () => follow.checked,
                          arrows: () => helpers.map((a) => ({ name: a.name, visible: a.visible, position: a.position.toArray() })) };
  document.body.dataset.follow = String(follow.checked);
}

main().catch((error) => {
  document.body.textContent = `symdyn viewer: ${error.message}`;
  document.body.dataset.error = error.message;
  window.symdynViewer = { ready: false, error: error.message };
});
