// The sva session viewer (sva view, docs/view.md): the object's true pose as a ghost, the hypotheses at their poses
// coloured by mass, the touches with their normals and numbers, and a slider over the readings that updates the
// hypotheses, the object probabilities and the errors. Reads the JSON in <script id="sva-data">; needs THREE and
// THREE.OrbitControls (inlined before it). window.svaView is the page's test hook; "#selftest" runs it on load.
(function () {
  "use strict";
  const errors = [];
  window.addEventListener("error", (e) => errors.push(String(e.message)));
  const consoleError = console.error.bind(console);
  console.error = (...args) => { errors.push(args.map(String).join(" ")); consoleError(...args); };

  const data = JSON.parse(document.getElementById("sva-data").textContent);
  const $ = (id) => document.getElementById(id);

  // Typed arrays from base64 (the meshes: float32 positions in mm, uint32 triangle indices).
  function decode(b64, Type) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  // R (rows) and T (mm), as the batch files write a pose: the pose that takes object coordinates to the robot frame.
  function poseMatrix(R, T) {
    const m = new THREE.Matrix4();
    m.set(...R[0], T[0], ...R[1], T[1], ...R[2], T[2], 0, 0, 0, 1);
    return m;
  }

  // Mass 0 -> blue, 1 -> red, through green: a hypothesis' colour.
  function massColour(p) {
    const c = new THREE.Color();
    c.setHSL((1 - Math.min(Math.max(p, 0), 1)) * 0.66, 0.85, 0.5);
    return c;
  }

  // ----- the scene
  const view = $("view");
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf7f7f7);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, 2, 3);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 1e6);
  camera.up.set(0, 0, 1);  // the robot frame's z up
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.addEventListener("change", render);

  const geometries = {};
  for (const [object, m] of Object.entries(data.meshes)) {
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(decode(m.positions, Float32Array), 3));
    g.setIndex(new THREE.BufferAttribute(decode(m.indices, Uint32Array), 1));
    g.computeVertexNormals();
    geometries[object] = g;
  }
  function objectMesh(object, material) {
    const mesh = new THREE.Mesh(geometries[object], material);
    mesh.matrixAutoUpdate = false;
    return mesh;
  }

  let meshCount = 0;
  if (data.truth && geometries[data.truth.object]) {
    const ghost = objectMesh(data.truth.object, new THREE.MeshBasicMaterial({ color: 0x888888, wireframe: true,
                                                                                transparent: true, opacity: 0.25 }));
    ghost.matrix.copy(poseMatrix(data.truth.R, data.truth.T));
    scene.add(ghost);
    meshCount += 1;
  }

  // The touches: a sphere each (the latest orange), its outward normal and its number.
  const extent = new THREE.Box3();
  for (const r of data.readings) extent.expandByPoint(new THREE.Vector3(...r.p));
  let objectSize = 0;
  for (const g of Object.values(geometries)) {
    g.computeBoundingSphere();
    objectSize = Math.max(objectSize, 2 * g.boundingSphere.radius);
  }
  // The markers' scale: the touched region or the objects, whichever is larger (mm).
  const size = Math.max(extent.getSize(new THREE.Vector3()).length(), objectSize, 20);
  const touches = [];
  // Markers shrink as touches crowd (1 up to 30 touches, a fifth at 1,000).
  const crowd = Math.min(1, Math.max(0.2, Math.sqrt(30 / data.readings.length)));
  const sphere = new THREE.SphereGeometry(size * 0.015 * crowd, 16, 12);
  function label(text) {
    const c = document.createElement("canvas");
    c.width = 64; c.height = 32;
    const g = c.getContext("2d");
    g.font = "bold 22px sans-serif"; g.fillStyle = "#222"; g.textAlign = "center"; g.textBaseline = "middle";
    g.fillText(text, 32, 16);
    const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
    const k = Math.max(crowd, 0.5);
    s.scale.set(size * 0.06 * k, size * 0.03 * k, 1);
    return s;
  }
  // One grey material for every touch and an orange sphere on the latest; the normals one line list; the numbers
  // made as they are first shown (a long session shows the latest kLabels): a page of 1,000 touches loads fast.
  const kLabels = 60;
  const dotMaterial = new THREE.MeshBasicMaterial({ color: 0x404040, depthTest: false, transparent: true });
  const normalPoints = new Float32Array(6 * data.readings.length);
  data.readings.forEach((r, i) => {
    const p = new THREE.Vector3(...r.p), n = new THREE.Vector3(...r.n).normalize();
    // Drawn over the objects (in the transparent pass, after the hypotheses): a touch inside a wrong hypothesis
    // stays visible.
    const dot = new THREE.Mesh(sphere, dotMaterial);
    dot.position.copy(p);
    dot.renderOrder = 2;
    dot.userData.reading = i;
    scene.add(dot);
    p.toArray(normalPoints, 6 * i);
    p.clone().addScaledVector(n, size * 0.08 * crowd).toArray(normalPoints, 6 * i + 3);
    touches.push({ dot, label: null, at: p.clone().addScaledVector(n, size * (0.08 * crowd + 0.03)) });
  });
  const normalGeometry = new THREE.BufferGeometry();
  normalGeometry.setAttribute("position", new THREE.BufferAttribute(normalPoints, 3));
  const normals = new THREE.LineSegments(normalGeometry, new THREE.LineBasicMaterial({ color: 0x3399ff,
                                                                                      depthTest: false,
                                                                                      transparent: true }));
  normals.renderOrder = 2;
  scene.add(normals);
  const latest = new THREE.Mesh(sphere, new THREE.MeshBasicMaterial({ color: 0xff8000, depthTest: false,
                                                                      transparent: true }));
  latest.scale.setScalar(1.25);
  latest.renderOrder = 3;
  scene.add(latest);
  function showTouches(current) {
    touches.forEach((t, k) => {
      t.dot.visible = k < current;
      const labelled = k < current && k >= current - kLabels;
      if (labelled && !t.label) {
        t.label = label(String(k + 1));
        t.label.position.copy(t.at);
        t.label.renderOrder = 3;
        scene.add(t.label);
      }
      if (t.label) t.label.visible = labelled;
    });
    normalGeometry.setDrawRange(0, 2 * current);
    latest.position.copy(touches[current - 1].dot.position);
  }

  // The hypotheses of the step shown (rebuilt when the slider moves).
  let hypothesisMeshes = [];
  function showHypotheses(step) {
    for (const m of hypothesisMeshes) { scene.remove(m); m.material.dispose(); }
    hypothesisMeshes = [];
    step.hypotheses.forEach((h, k) => {
      // The best always; the others while they hold a share worth seeing.
      if (!geometries[h.object] || (k > 0 && h.probability < 0.01)) return;
      const material = new THREE.MeshLambertMaterial({ color: massColour(h.probability), transparent: true,
                                                       opacity: 0.35 + 0.55 * h.probability });
      const mesh = objectMesh(h.object, material);
      mesh.matrix.copy(poseMatrix(h.R, h.T));
      scene.add(mesh);
      hypothesisMeshes.push(mesh);
    });
  }

  // ----- the side panel
  const fmt = (v, d) => (v === null || v === undefined ? "-" : Number(v).toFixed(d));
  // Names come from files (a map, a dataset, a sessions file: someone else's, maybe): the panel is built of elements
  // and text nodes, never parsed from a string, so a name shows as written and runs nothing (docs/view.md).
  function el(tag, className = "", text = null) {
    const e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== null) e.textContent = text;
    return e;
  }
  function bar(name, p, colour) {
    const label = el("span", "name", String(name));
    label.title = String(name);
    const fill = el("div", "fill");
    fill.style.width = `${(100 * p).toFixed(1)}%`;
    fill.style.background = colour;
    const track = el("span", "track");
    track.append(fill);
    const row = el("div", "bar");
    row.append(label, track, el("span", "value", `${(100 * p).toFixed(1)}%`));
    return row;
  }
  function showPanel(i, step) {
    $("step-label").textContent = `reading ${i} of ${data.readings.length}`;
    $("slider-label").textContent = `${i} / ${data.readings.length} (${fmt(step.update_ms, 1)} ms update)`;
    const truth = data.truth ? data.objects[data.truth.object] : null;
    const named = step.object === null ? "no answer yet" : data.objects[step.object];
    const e = step.error;
    $("errors").replaceChildren("estimate: ", el("b", "", String(named)), truth ? ` (truth: ${truth})` : "", el("br"),
      e ? `error: ${fmt(e.translation_mm, 2)} mm, ${fmt(e.angle_deg, 2)}\u00b0` : "error: -", el("br"),
      `none of these: ${fmt(100 * step.p_unknown, 1)}%`);
    const order = step.probabilities.map((p, o) => [p, o]).sort((a, b) => b[0] - a[0]).slice(0, 12);
    $("bars").replaceChildren(...order.map(([p, o]) =>
      bar(data.objects[o], p * (1 - step.p_unknown), data.truth && o === data.truth.object ? "#2ca02c" : "#1f77b4")),
      bar("none of these", step.p_unknown, "#999"));
    const lines = [];
    step.hypotheses.forEach((h, k) => {
      const square = el("span", "", "\u25a0");
      square.style.color = `#${massColour(h.probability).getHexString()}`;
      if (k > 0) lines.push(el("br"));
      lines.push(`${k + 1}. ${data.objects[h.object]} `, square, ` ${fmt(100 * h.probability, 1)}%`);
    });
    $("hypotheses").replaceChildren(...(lines.length ? lines : ["none yet"]));
  }

  let current = 1;
  function setReading(i) {
    current = Math.min(Math.max(1, Math.round(i)), data.readings.length);
    $("slider").value = String(current);
    showTouches(current);
    const step = data.steps[current - 1];
    showHypotheses(step);
    showPanel(current, step);
    render();
  }

  // ----- hover: a touch's pressure image
  const ray = new THREE.Raycaster(), mouse = new THREE.Vector2();
  renderer.domElement.addEventListener("mousemove", (ev) => {
    const rect = renderer.domElement.getBoundingClientRect();
    mouse.set(((ev.clientX - rect.left) / rect.width) * 2 - 1, -((ev.clientY - rect.top) / rect.height) * 2 + 1);
    ray.setFromCamera(mouse, camera);
    const hit = ray.intersectObjects(touches.filter((t) => t.dot.visible).map((t) => t.dot))[0];
    if (!hit) { $("tip").style.display = "none"; return; }
    showTip(hit.object.userData.reading, ev.clientX - rect.left + 12, ev.clientY - rect.top + 12);
  });
  function showTip(i, x, y) {
    const r = data.readings[i], tip = $("tip");
    drawPressure($("tip-image"), r);
    $("tip-text").textContent = `touch ${i + 1}: max ${fmt(Math.max(...r.pressure), 1)} kPa`;
    tip.style.left = `${x}px`;
    tip.style.top = `${y}px`;
    tip.style.display = "block";
  }
  function drawPressure(canvas, r) {
    const g = canvas.getContext("2d"), top = Math.max(...r.pressure, 1e-9);
    const w = canvas.width / r.cols, h = canvas.height / r.rows;
    r.pressure.forEach((v, k) => {
      const c = new THREE.Color().setHSL(0.66 * (1 - Math.max(v, 0) / top), 0.9, 0.5);
      g.fillStyle = `#${c.getHexString()}`;
      g.fillRect((k % r.cols) * w, Math.floor(k / r.cols) * h, w, h);
    });
  }

  // ----- layout and drawing
  function render() { renderer.render(scene, camera); }
  function resize(draw = true) {
    const w = Math.max(view.clientWidth, 100), h = Math.max(view.clientHeight, 100);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    if (draw) render();
  }
  // The view takes in the touches and the objects (the truth, else the last step's best hypothesis).
  function expandByObject(box, object, R, T) {
    const g = geometries[object];
    if (!g) return;
    const s = g.boundingSphere.clone().applyMatrix4(poseMatrix(R, T));
    box.expandByPoint(s.center.clone().addScalar(s.radius));
    box.expandByPoint(s.center.clone().addScalar(-s.radius));
  }
  function frame() {
    const box = extent.clone();
    const last = data.steps[data.steps.length - 1].hypotheses[0];
    if (data.truth) expandByObject(box, data.truth.object, data.truth.R, data.truth.T);
    else if (last) expandByObject(box, last.object, last.R, last.T);
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() * 0.5, size * 0.5);
    camera.position.copy(centre).add(new THREE.Vector3(1.2, -1.6, 1.0).normalize().multiplyScalar(radius * 2.3));
    camera.near = radius * 0.01;
    camera.far = radius * 100;
    controls.target.copy(centre);
    controls.update();
  }
  $("title").textContent = data.title;
  document.title = data.title;
  $("meta").textContent = `scene ${data.scene} · map ${data.map} · ${data.source} · backend ${data.backend} · ` +
    `median ${fmt(data.update_ms_median, 1)} ms per update`;
  const slider = $("slider");
  slider.max = String(data.readings.length);
  slider.addEventListener("input", () => setReading(Number(slider.value)));
  window.addEventListener("resize", () => resize());
  frame();
  resize(false);  // setReading below draws the first frame (one drawing on load: software WebGL is slow)
  setReading(data.readings.length);

  // ----- the test hook
  window.svaView = {
    setReading,
    reading: () => current,
    counts: () => ({ meshes: meshCount + hypothesisMeshes.length, contacts: touches.filter((t) => t.dot.visible).length,
                     hypotheses: hypothesisMeshes.length }),
    probabilities: () => data.steps[current - 1].probabilities.slice(),
    topProbability: () => {
      const s = data.steps[current - 1];
      return s.object === null ? 0 : s.probabilities[s.object];
    },
    errors: () => errors.slice(),
    // What hovering over touch i shows: its text, and how many of its image's pixels are coloured.
    hover: (i) => {
      showTip(i, 20, 20);
      const c = $("tip-image"), px = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
      let coloured = 0;
      for (let k = 0; k < px.length; k += 4) coloured += px[k + 3] > 0 && !(px[k] === px[k + 1] && px[k] === px[k + 2]);
      return { text: $("tip-text").textContent, coloured };
    },
  };
  // "#load": how long the page took from navigation to its first full drawing (docs/view.md, "Size and speed").
  if (location.hash === "#load") {
    const triangles = Object.values(data.meshes).reduce((n, m) => n + m.triangles, 0);
    $("sva-selftest").textContent = JSON.stringify({ load_ms: performance.now(), readings: data.readings.length,
                                                     triangles, errors: errors.slice() });
  }
  if (location.hash === "#selftest") {
    const out = { readings: data.readings.length, steps: [] };
    for (let i = 1; i <= data.readings.length; ++i) {
      setReading(i);
      out.steps.push({ reading: i, counts: window.svaView.counts(), top_probability: window.svaView.topProbability(),
                       p_unknown: data.steps[i - 1].p_unknown, bars: document.querySelectorAll("#bars .bar").length });
    }
    setReading(data.readings.length);
    out.hover = window.svaView.hover(data.readings.length - 1);
    out.errors = errors.slice();
    $("sva-selftest").textContent = JSON.stringify(out);
  }
})();
