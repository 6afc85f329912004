// The interactive view of a surface and its lines, written into every HTML file of
// `crestline view`: three.js (embedded as text in the element #three, loaded as a
// module from a Blob, so that the file needs no network), the scene from the JSON in
// #scene, a drag-to-rotate, wheel-to-zoom camera, a panel to toggle each family and
// colour the surface by a curvature quantity, and a click on a line to see its kind,
// length and strength.
//
// The URL fragment sets the initial state, e.g. `view.html#hide=ridges&color=mean`:
// the hidden families' boxes are clicked, the colouring chosen in its menu.

const THREE = await import(
  URL.createObjectURL(new Blob([document.getElementById("three").textContent], { type: "text/javascript" }))
);
const scene_data = JSON.parse(document.getElementById("scene").textContent);

function bytes(base64) {
  const text = atob(base64);
  const out = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) out[i] = text.charCodeAt(i);
  return out.buffer;
}
const floats = (base64) => new Float32Array(bytes(base64));
const indices = (base64) => new Uint32Array(bytes(base64));

const options = new URLSearchParams(location.hash.slice(1));
const hidden = new Set((options.get("hide") || "").split(",").filter((s) => s));

// Renderer, scene, camera and lights.
const canvas = document.getElementById("view");
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(scene_data.background);
const center = new THREE.Vector3(...scene_data.center);
const radius = scene_data.radius;
const camera = new THREE.PerspectiveCamera(30, 1, radius / 100, radius * 100);
scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 1.6));
const headlight = new THREE.DirectionalLight(0xffffff, 1.4);
camera.add(headlight);
scene.add(camera);

// The surface, pushed back a little so that lines on it are drawn over it.
const surface_geometry = new THREE.BufferGeometry();
surface_geometry.setAttribute("position", new THREE.BufferAttribute(floats(scene_data.positions), 3));
surface_geometry.setIndex(new THREE.BufferAttribute(indices(scene_data.triangles), 1));
surface_geometry.computeVertexNormals();
const grey = new THREE.Color(scene_data.surface_color);
const surface_material = new THREE.MeshLambertMaterial({
  color: 0xffffff,
  vertexColors: true,
  side: THREE.DoubleSide,
  polygonOffset: true,
  polygonOffsetFactor: 1,
  polygonOffsetUnits: 1,
});
const vertex_count = surface_geometry.getAttribute("position").count;
const colors = new Float32Array(3 * vertex_count);
surface_geometry.setAttribute("color", new THREE.BufferAttribute(colors, 3));
scene.add(new THREE.Mesh(surface_geometry, surface_material));

// Diverging colours for a signed quantity: blue (negative), grey (0), red (positive),
// saturated at the 95th percentile of its magnitude.
function color_surface(name) {
  const values = name && scene_data.quantities[name] ? floats(scene_data.quantities[name]) : null;
  let scale = 1;
  if (values) {
    const magnitudes = Array.from(values, Math.abs).filter(Number.isFinite).sort((a, b) => a - b);
    scale = magnitudes[Math.floor(0.95 * (magnitudes.length - 1))] || 1;
  }
  const blue = new THREE.Color(0x2166ac), red = new THREE.Color(0xb2182b), c = new THREE.Color();
  for (let v = 0; v < vertex_count; v++) {
    const t = values && Number.isFinite(values[v]) ? Math.max(-1, Math.min(1, values[v] / scale)) : 0;
    c.copy(grey).lerp(t < 0 ? blue : red, Math.abs(t));
    colors.set([c.r, c.g, c.b], 3 * v);
  }
  surface_geometry.getAttribute("color").needsUpdate = true;
}

// The line families, each a set of segments with the line each segment belongs to.
const families = scene_data.families.map((family) => {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(floats(family.segments), 3));
  const material = new THREE.LineBasicMaterial({ color: family.color });
  const object = new THREE.LineSegments(geometry, material);
  object.userData = { family, line_of_segment: indices(family.line_of_segment) };
  scene.add(object);
  return object;
});

// The panel: a checkbox per family, the colouring of the surface, the picked line.
const panel = document.getElementById("families");
for (const object of families) {
  const { family } = object.userData;
  const label = document.createElement("label");
  const box = document.createElement("input");
  box.type = "checkbox";
  box.checked = object.visible;
  box.dataset.family = family.name;
  box.addEventListener("change", () => {
    object.visible = box.checked;
    render();
  });
  const swatch = document.createElement("span");
  swatch.className = "swatch";
  swatch.style.background = family.color;
  label.append(box, swatch, ` ${family.name} (${family.lines.length})`);
  panel.append(label);
}
const coloring = document.getElementById("color");
for (const name of Object.keys(scene_data.quantities)) coloring.add(new Option(name, name));
coloring.value = options.get("color") || "";
coloring.addEventListener("change", () => {
  color_surface(coloring.value);
  render();
});
color_surface(coloring.value);

// Camera: orbit about the centre by dragging, zoom with the wheel.
let azimuth = 0, elevation = 0, distance = 4 * radius;
function place_camera() {
  const c = Math.cos(elevation);
  camera.position.set(
    center.x + distance * c * Math.sin(azimuth),
    center.y + distance * Math.sin(elevation),
    center.z + distance * c * Math.cos(azimuth),
  );
  camera.lookAt(center);
}
let drag = null;
canvas.addEventListener("pointerdown", (e) => {
  drag = { x: e.clientX, y: e.clientY, moved: false };
});
window.addEventListener("pointerup", (e) => {
  if (drag && !drag.moved) pick(e);
  drag = null;
});
window.addEventListener("pointermove", (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
  azimuth -= dx * 0.01;
  elevation = Math.max(-1.55, Math.min(1.55, elevation + dy * 0.01));
  drag.x = e.clientX;
  drag.y = e.clientY;
  render();
});
canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  distance = Math.max(radius * 0.2, Math.min(radius * 50, distance * Math.exp(e.deltaY * 0.001)));
  render();
}, { passive: false });

// Picking: the nearest visible line segment under the pointer.
const raycaster = new THREE.Raycaster();
const info = document.getElementById("info");
function pick(e) {
  const box = canvas.getBoundingClientRect();
  const pointer = new THREE.Vector2(
    ((e.clientX - box.left) / box.width) * 2 - 1,
    -((e.clientY - box.top) / box.height) * 2 + 1,
  );
  raycaster.setFromCamera(pointer, camera);
  raycaster.params.Line.threshold = radius * 0.01;
  const hit = raycaster.intersectObjects(families.filter((f) => f.visible))[0];
  if (!hit) {
    info.textContent = "";
    return;
  }
  const { family, line_of_segment } = hit.object.userData;
  const line = family.lines[line_of_segment[hit.index / 2]];
  info.textContent =
    `${line.kind}: length ${line.length.toPrecision(4)}, strength ${line.strength.toPrecision(4)}` +
    (line.closed ? ", closed" : "");
}

function render() {
  place_camera();
  renderer.render(scene, camera);
}
function resize() {
  const { clientWidth: w, clientHeight: h } = canvas;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  render();
}
window.addEventListener("resize", resize);
resize();
// The fragment's hidden families are unticked as a click would, through their boxes.
for (const box of panel.querySelectorAll("input")) {
  if (hidden.has(box.dataset.family)) box.click();
}
document.body.dataset.ready = "true";
