// The viewer page: terrain, contact surfaces, root path, footholds and the robot walking through
// the plan's states or the run's trace, with a timeline and plots. From a file (a plan, a
// simulated run, a run's log) everything is in the page; live, the run grows as live_bridge
// forwards the processes' messages (viewer/live.js). A run on the mapped terrain (run_log's
// `perception`) adds its elevation map, the true terrain and the map's metrics.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { baseMatrix, hipPositions, linkPoses } from 'viewer/kinematics.js';
import { connectLive } from 'viewer/live.js';
import { ganttPlot, linePlot } from 'viewer/plots.js';
import { convexHull, polygonMargin } from 'viewer/support.js';

const LEGS = ['LF', 'RF', 'LH', 'RH'];
const LEG_COLORS = { LF: '#e41a1c', RF: '#33a02c', LH: '#1f78b4', RH: '#ffcc00' };
const JOINT_KINDS = ['HAA', 'HFE', 'KFE'];
const COLORS = {
  terrain: '#cdbf9f',
  terrainEdges: '#8c7f64',
  surface: '#7ec8e3',
  rootPath: '#8e44ad',
  simPath: '#ff7f0e',
  trunk: '#d5d9df',
  actuator: '#7d838c',
  leg: '#555b63',
  background: '#eef1f5',
  limit: '#c62828',
  comReference: '#e377c2',
  zmpReference: '#17becf',
  cop: '#ff00ff',
  support: '#3f6ea8',
  truth: '#4a5a78',
  truthEdges: '#1f2a3d',
};
// The elevation map's colours from its lowest to its highest cells (viridis).
const HEIGHT_SCALE = ['#440154', '#3b528b', '#21918c', '#5ec962', '#fde725'];

const data = JSON.parse(document.getElementById('rbcp-data').textContent);
const run = data.run;
const sceneData = data.scene;
const robot = sceneData.robot;
const liveUrl = data.live ? liveSocketUrl(data.live) : null;
// What the robot mapped, for a run on the mapped terrain (run_log's `perception`); else null.
const perception = run.perception && typeof run.perception === 'object' ? run.perception : null;
const $ = (id) => document.getElementById(id);
const v3 = (a) => new THREE.Vector3(a[0], a[1], a[2]);

/** The bridge's websocket: ?ws=URL, else the page's own host when served by the bridge, else the
 *  port the page was made for. */
function liveSocketUrl(live) {
  const asked = new URLSearchParams(location.search).get('ws');
  if (asked) return asked;
  if (location.protocol === 'http:') return `ws://${location.host}/ws`;
  return `ws://127.0.0.1:${live.port}/ws`;
}

// ---- Tracks: what the timeline plays -------------------------------------------------------------

/** Linear interpolation of angles along the shorter way round. */
function lerpAngle(a, b, f) {
  const d = Math.atan2(Math.sin(b - a), Math.cos(b - a));
  return a + d * f;
}

function lerpFrame(a, b, f) {
  const lerp = (x, y) => x.map((v, i) => v + (y[i] - v) * f);
  return {
    ...a,
    t: a.t + (b.t - a.t) * f,
    position: lerp(a.position, b.position),
    rpy: a.rpy.map((v, i) => lerpAngle(v, b.rpy[i], f)),
    joints: a.joints && b.joints ? lerp(a.joints, b.joints) : null,
    feet: a.feet && b.feet
      ? Object.fromEntries(LEGS.map((leg) => [leg, { position: lerp(a.feet[leg].position, b.feet[leg].position), contact: a.feet[leg].contact }]))
      : null,
  };
}

function makeTrack(kind, frames) {
  return {
    kind,
    frames,
    duration: frames.length ? frames[frames.length - 1].t : 0,
    /** The pose at time t, interpolated between the frames around it. */
    at(t) {
      let lo = 0;
      let hi = frames.length - 1;
      if (t <= frames[0].t) return frames[0];
      if (t >= frames[hi].t) return frames[hi];
      while (hi - lo > 1) {
        const mid = (lo + hi) >> 1;
        if (frames[mid].t <= t) lo = mid;
        else hi = mid;
      }
      const a = frames[lo];
      const b = frames[hi];
      return lerpFrame(a, b, (t - a.t) / (b.t - a.t || 1));
    },
  };
}

/** One frame of a simulated trace or a run's log (TraceSample JSON). */
function traceFrame(s, i) {
  return {
    t: s.t,
    index: i,
    position: s.base.position,
    rpy: s.base.rpy,
    joints: Array.isArray(s.joints) && s.joints.length === 12 ? s.joints : null,
    torques: Array.isArray(s.torques) ? s.torques : null,
    margin: s.support_margin_m ?? null,
    feet: Object.fromEntries(s.feet.map((f) => [f.leg, { position: f.position, contact: f.contact }])),
    comReference: xyOrNull(s.com_reference),
    zmpReference: xyOrNull(s.zmp_reference),
    cop: xyOrNull(s.cop),
  };
}

/** [x, y] when `a` is a pair of finite numbers (a trace's com_reference, zmp_reference, cop), else null. */
function xyOrNull(a) {
  return Array.isArray(a) && a.length === 2 && a.every(Number.isFinite) ? a : null;
}

/** What the trace carries of the balance: references (dynamic walk), the centre of pressure. */
function traceBalance() {
  const trace = run.sim_trace || [];
  return {
    references: trace.some((s) => xyOrNull(s.com_reference) || xyOrNull(s.zmp_reference)),
    cop: trace.some((s) => 'cop' in s),
  };
}

let tracks = {};
function buildTracks() {
  const states = run.states || [];
  const trace = run.sim_trace || [];
  const rootSamples = run.root_path || [];
  tracks = {};
  if (states.length && !data.live) {
    tracks.plan = makeTrack(
      'plan',
      states.map((s, i) => ({
        t: i,
        index: i,
        position: s.base.position,
        rpy: s.base.rpy,
        joints: s.joints,
        feet: Object.fromEntries(s.feet.map((f) => [f.leg, { position: f.position, contact: true }])),
        moving_leg: s.moving_leg,
      })),
    );
  }
  if (trace.length) tracks.sim = makeTrack('sim', trace.map(traceFrame));
  if (rootSamples.length > 1) {
    // The planned trunk path alone: position and heading, no legs.
    tracks.root = makeTrack(
      'root',
      rootSamples.map((p, i) => ({ t: p.t, index: i, position: p.position, rpy: [0, 0, p.yaw], joints: null, feet: null })),
    );
  }
}

// ---- Header, legend, summary ---------------------------------------------------------------------

function setStatus(kind, text) {
  const status = $('status');
  status.className = `status ${kind}`;
  status.textContent = text;
}

function renderHeader() {
  const name = run.scenario || sceneData.scenario || (data.live ? 'live' : 'plan');
  $('title').textContent = `${name}${run.seed !== undefined ? ` · seed ${run.seed}` : ''}`;
  $('source').textContent = data.live ? `live from ${liveUrl}` : data.source.plan;
  if (data.live) return;  // the live status line follows the connection (live.js)
  const trace = run.sim_trace || [];
  if (run.failure) {
    setStatus('failed', `failure: ${typeof run.failure === 'string' ? run.failure : JSON.stringify(run.failure)}`);
  } else if (run.outcome !== undefined) {
    // A run's log: the simulator's verdict.
    setStatus(run.sim_ok ? 'ok' : 'failed', run.sim_ok ? `run reached the goal: ${run.steps} steps walked` : `run: ${run.outcome}`);
  } else if (trace.length || run.sim_ok !== undefined) {
    setStatus(run.sim_ok ? 'ok' : 'failed', run.sim_ok ? 'simulated run reached the goal' : 'simulated run did not succeed');
  } else if (run.contact_ok) {
    setStatus('ok', `contact plan: ${run.steps} steps${run.reached_goal ? ' to the goal' : ''}`);
  } else {
    setStatus('neutral', run.root_ok ? 'root path only' : 'no plan');
  }
}

function formatValue(v) {
  if (typeof v === 'number') return Number.isInteger(v) ? String(v) : String(Number(v.toPrecision(4)));
  if (v === null) return '—';
  if (typeof v === 'object') return JSON.stringify(v);
  return String(v);
}

function renderSummary() {
  const first = ['scenario', 'seed', 'outcome', 'root_status', 'root_s', 'root_duration_s', 'contact_status', 'contact_s', 'steps',
    'reached_goal', 'sim_ok', 'fell', 'sim_time_s', 'steps_executed', 'steps_total', 'plans', 'unanswered_waits',
    'replan_latency_ms', 'collisions', 'collision_links', 'max_torque_ratio', 'min_support_margin_m', 'final_base_error_m',
    'early_touchdowns', 'late_touchdowns'];
  const skip = new Set(['states', 'root_path', 'sim_trace', 'failure', 'joint_names', 'replans', 'terrain',
    'contact_surfaces', 'start', 'goal', 'sim_failure', 'schema_version']);
  if (perception) skip.add('perception');  // its own panel
  const keys = [...first.filter((k) => k in run), ...Object.keys(run).filter((k) => !first.includes(k) && !skip.has(k))];
  const rows = keys
    .filter((k) => !Array.isArray(run[k]) && !(k === 'collision_links' && !Object.keys(run[k] ?? {}).length))
    .map((k) => `<tr><th>${escapeHtml(k)}</th><td>${escapeHtml(formatValue(run[k]))}</td></tr>`);
  if ((run.missing_plans || []).length) {
    rows.push(`<tr><th>missing plans</th><td>${escapeHtml(run.missing_plans.join('; '))} (their steps are not drawn)</td></tr>`);
  }
  if (sceneData.terrain) {
    rows.push(`<tr><th>terrain</th><td>${sceneData.terrain.triangles.length} triangles, ${(sceneData.contact_surfaces || []).length} surfaces</td></tr>`);
  }
  if (data.checks && data.checks.feet_error_m !== null && data.checks.feet_error_m !== undefined) {
    rows.push(`<tr><th>FK check</th><td>plan feet within ${data.checks.feet_error_m.toExponential(1)} m of the viewer's kinematics</td></tr>`);
  }
  $('summary').innerHTML = rows.join('');
}

/** The perception panel: how well the map matches the true terrain, how much of the walk it
 *  covered, how late maps came; the elevation map's colour scale. */
function renderPerception() {
  if (!perception) return;
  const mm = (m) => (Number.isFinite(m) ? `${(m * 1000).toFixed(1)} mm` : '—');
  const ms = (m) => (Number.isFinite(m) ? `${m.toFixed(1)} ms` : '—');
  const e = perception.height_error_m;
  const latency = perception.cloud_to_terrain_ms;
  const map = perception.elevation_map;
  const rows = [
    ['height error', e ? `RMS ${mm(e.rms)} · p95 ${mm(e.p95)} · max ${mm(e.max)} (${e.cells} cells)` : '—'],
    ['path coverage', Number.isFinite(perception.path_coverage) ? `${(perception.path_coverage * 100).toFixed(1)} % of the walked path` : '—'],
    ['cloud → terrain', latency ? `median ${ms(latency.median)} · p95 ${ms(latency.p95)} (${latency.count} measured)` : '—'],
    ['known cells', `${formatValue(perception.known_cells ?? null)}${map ? ` (${(map.resolution * 100).toFixed(0)} cm cells)` : ''}`],
    ['clouds, maps', `${formatValue(perception.clouds ?? null)} clouds, ${formatValue(perception.maps ?? null)} maps`],
  ].map(([k, v]) => `<tr><th>${escapeHtml(k)}</th><td>${escapeHtml(v)}</td></tr>`);
  const range = map && heightRange(map);
  if (range) {
    rows.push(`<tr><th>map height</th><td><span class="scale" style="background:${heightGradient()}"></span>` +
      `${range[0].toFixed(3)} to ${range[1].toFixed(3)} m</td></tr>`);
  }
  if (perception.problem) rows.push(`<tr><th>problem</th><td>${escapeHtml(perception.problem)}</td></tr>`);
  $('perception').innerHTML = rows.join('');
  $('perception').hidden = $('perception-title').hidden = false;
}

function escapeHtml(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
}

function renderLegend() {
  const items = [
    ...LEGS.map((leg) => [LEG_COLORS[leg], `${leg} foothold / foot`, 'disc']),
    [COLORS.terrain, 'terrain', 'box'],
    [COLORS.surface, 'contact surface', 'box'],
    [COLORS.rootPath, 'root path (dots: plan states)', 'line'],
    ['#333333', 'start and goal (arrows)', 'line'],
  ];
  if ((run.sim_trace || []).length || data.live) items.push([COLORS.simPath, 'base path walked', 'line']);
  const balance = traceBalance();
  if (balance.references) {
    items.push([COLORS.comReference, 'CoM reference (dynamic walk)', 'line']);
    items.push([COLORS.zmpReference, 'ZMP reference (dynamic walk)', 'line']);
  }
  if (balance.cop) {
    items.push([COLORS.support, 'support polygon (feet in contact)', 'box']);
    items.push([COLORS.cop, 'centre of pressure', 'disc']);
  }
  if (perception && perception.elevation_map) items.push([heightGradient(), 'elevation map (by height)', 'box']);
  if (perception && perception.true_terrain) items.push([COLORS.truth, 'true terrain (shows where the map is 1 cm lower or unknown)', 'box']);
  $('legend').innerHTML = items
    .map(([color, label, shape]) => `<li><span class="swatch ${shape}" style="background:${color}"></span>${label}</li>`)
    .join('');
}

// ---- 3D scene ------------------------------------------------------------------------------------

const layers = {};
const hidden = new Set();  // layers the user switched off
// The scene is drawn again only when something changed (a pose, a layer, the camera, the size).
let dirty = true;
const invalidate = () => {
  dirty = true;
};

/** Puts `object` in the scene as layer `name`, replacing (and freeing) the one before. */
function setLayerObject(name, object) {
  const old = layers[name];
  if (old && view) {
    view.scene.remove(old);
    old.traverse((o) => {
      if (o.geometry && !o.userData.sharedGeometry) o.geometry.dispose();
    });
  }
  layers[name] = object;
  object.visible = !hidden.has(name);
  if (view) view.scene.add(object);
  invalidate();
  const box = document.querySelector(`#layers [data-layer=${name}]`);
  if (box) box.closest('label').hidden = false;
  return object;
}

/** An indexed geometry of a terrain piece ({vertices, triangles}). */
function terrainGeometry({ vertices, triangles }) {
  const indexed = new THREE.BufferGeometry();
  indexed.setAttribute('position', new THREE.Float32BufferAttribute(vertices.flat(), 3));
  indexed.setIndex(triangles.flat());
  return indexed;
}

function terrainMesh() {
  const group = new THREE.Group();
  if (!sceneData.terrain) return group;
  const indexed = terrainGeometry(sceneData.terrain);
  const geometry = indexed.toNonIndexed();
  geometry.computeVertexNormals();
  const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: COLORS.terrain, roughness: 0.95 }));
  mesh.receiveShadow = true;
  group.add(mesh);
  group.add(new THREE.LineSegments(new THREE.EdgesGeometry(indexed, 20), new THREE.LineBasicMaterial({ color: COLORS.terrainEdges })));
  return group;
}

/** The elevation map's known heights' range [m] the colours span: the 1st to the 99th
 *  percentile, widened to 5 cm at least (the noise of flat ground keeps one colour); null when
 *  no cell is known. */
function heightRange(map) {
  const known = map.height.filter(Number.isFinite).sort((a, b) => a - b);
  if (!known.length) return null;
  const at = (q) => known[Math.min(known.length - 1, Math.floor(q * known.length))];
  const [lo, hi] = [at(0.01), at(0.99)];
  const widen = Math.max(0, 0.05 - (hi - lo)) / 2;
  return [lo - widen, hi + widen];
}

/** The colour of f in [0, 1] on HEIGHT_SCALE (linear working colour space). */
function scaleColor(f, out = new THREE.Color()) {
  const x = Math.min(Math.max(f, 0), 1) * (HEIGHT_SCALE.length - 1);
  const i = Math.min(Math.floor(x), HEIGHT_SCALE.length - 2);
  return out.set(HEIGHT_SCALE[i]).lerp(new THREE.Color(HEIGHT_SCALE[i + 1]), x - i);
}

/** HEIGHT_SCALE as a CSS gradient, for the legend and the perception panel. */
function heightGradient() {
  return `linear-gradient(90deg, ${HEIGHT_SCALE.join(', ')})`;
}

/** The elevation map: one square tile per known cell, coloured by height, 2 mm above the cell's
 *  height: over the mapped terrain, under the contact surfaces (4 mm) and the footholds. */
function elevationTiles() {
  const map = perception.elevation_map;
  const range = heightRange(map);
  if (!range) return new THREE.Group();
  const { num_x: nx, num_y: ny, resolution: r } = map;
  const [x0, y0] = map.origin;
  const positions = [];
  const colors = [];
  const index = [];
  const color = new THREE.Color();
  for (let iy = 0; iy < ny; iy++) {
    for (let ix = 0; ix < nx; ix++) {
      const h = map.height[iy * nx + ix];
      if (!Number.isFinite(h)) continue;
      const z = h + 0.002;
      const x = x0 + ix * r;
      const y = y0 + iy * r;
      const k = positions.length / 3;
      positions.push(x, y, z, x + r, y, z, x + r, y + r, z, x, y + r, z);
      scaleColor((h - range[0]) / (range[1] - range[0]), color);
      for (let c = 0; c < 4; c++) colors.push(color.r, color.g, color.b);
      index.push(k, k + 1, k + 2, k, k + 2, k + 3);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
  geometry.setIndex(index);
  geometry.computeVertexNormals();
  const mesh = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({ vertexColors: true }));
  mesh.receiveShadow = true;
  return mesh;
}

/** The true terrain (the simulator's), translucent, 1 cm under its place: it shows through where
 *  the map lies more than 1 cm below it or knows nothing. Its edges in place, just above it,
 *  drawn after its faces so that those behind them stay hidden. */
function trueTerrain() {
  const group = new THREE.Group();
  const indexed = terrainGeometry(perception.true_terrain);
  const surface = new THREE.Mesh(indexed, new THREE.MeshBasicMaterial({ color: COLORS.truth, transparent: true, opacity: 0.3 }));
  surface.position.z = -0.01;
  surface.renderOrder = 1;
  const edges = new THREE.LineSegments(new THREE.EdgesGeometry(indexed, 20),
    new THREE.LineBasicMaterial({ color: COLORS.truthEdges, transparent: true }));
  edges.position.z = 0.004;
  edges.renderOrder = 2;
  group.add(surface, edges);
  return group;
}

function surfaceMeshes() {
  const group = new THREE.Group();
  const fill = new THREE.MeshBasicMaterial({
    color: COLORS.surface, transparent: true, opacity: 0.4, side: THREE.DoubleSide, depthWrite: false,
  });
  const edge = new THREE.LineBasicMaterial({ color: '#2b7a99' });
  for (const s of sceneData.contact_surfaces || []) {
    const lift = v3(s.normal).multiplyScalar(0.004);
    const points = s.vertices.map((p) => v3(p).add(lift));
    const positions = [];
    for (let i = 1; i + 1 < points.length; i++) positions.push(...points[0].toArray(), ...points[i].toArray(), ...points[i + 1].toArray());
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    group.add(new THREE.Mesh(geometry, fill));
    group.add(new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(points), edge));
  }
  return group;
}

/** A tube along a polyline (WebGL lines are one pixel wide). */
function polylineTube(points, color, radius) {
  const path = new THREE.CurvePath();
  for (let i = 1; i < points.length; i++) {
    if (points[i].distanceTo(points[i - 1]) > 1e-6) path.add(new THREE.LineCurve3(points[i - 1], points[i]));
  }
  if (!path.curves.length) return new THREE.Group();
  const geometry = new THREE.TubeGeometry(path, Math.max(8, path.curves.length * 2), radius, 6, false);
  return new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color, roughness: 0.6 }));
}

/** The states whose footholds and base positions are drawn: the plan, or live the walked steps
 *  and the current plan ahead. */
function drawnStates() {
  return [...(run.states || []), ...(run.plan_ahead || [])];
}

function rootPath() {
  const group = new THREE.Group();
  const points = (run.root_path || []).map((p) => v3(p.position));
  if (points.length > 1) group.add(polylineTube(points, COLORS.rootPath, 0.007));
  const dot = new THREE.SphereGeometry(0.014, 12, 8);
  const material = new THREE.MeshStandardMaterial({ color: COLORS.rootPath });
  for (const s of drawnStates()) {
    const mesh = new THREE.Mesh(dot, material);
    mesh.position.fromArray(s.base.position);
    group.add(mesh);
  }
  return group;
}

function simPath() {
  const points = (run.sim_trace || []).map((s) => v3(s.base.position));
  return points.length > 1 ? polylineTube(points, COLORS.simPath, 0.005) : new THREE.Group();
}

/** Height [m] of the feet in contact in a trace sample (their mean), null with none. */
function contactHeight(s) {
  const down = s.feet.filter((f) => f.contact);
  return down.length ? down.reduce((sum, f) => sum + f.position[2], 0) / down.length : null;
}

/** The dynamic walk's CoM and ZMP references over the run: two lines on the ground, at the
 *  height of the feet in contact, broken where the trace has no reference. */
function referenceTrails() {
  const group = new THREE.Group();
  for (const [key, color] of [['com_reference', COLORS.comReference], ['zmp_reference', COLORS.zmpReference]]) {
    let z = null;
    let piece = [];
    const pieces = [piece];
    for (const s of run.sim_trace || []) {
      z = contactHeight(s) ?? z;
      const xy = xyOrNull(s[key]);
      if (xy && z !== null) piece.push(new THREE.Vector3(xy[0], xy[1], z + 0.008));
      else if (piece.length) pieces.push((piece = []));
    }
    for (const points of pieces) if (points.length > 1) group.add(polylineTube(points, color, 0.004));
  }
  return group;
}

/** The support polygon of the feet in contact and the centre of pressure at the frame shown,
 *  on the ground under the robot; show(frame) moves them. */
function supportView() {
  const group = new THREE.Group();
  const geometry = new THREE.BufferGeometry();
  const polygon = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
    color: COLORS.support, transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false,
  }));
  const edge = new THREE.LineLoop(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: COLORS.support }));
  const cop = new THREE.Mesh(new THREE.CylinderGeometry(0.022, 0.022, 0.004, 24), new THREE.MeshBasicMaterial({ color: COLORS.cop }));
  cop.rotation.x = Math.PI / 2;  // the disc lies flat
  group.add(polygon, edge, cop);
  group.userData.show = (frame) => {
    const down = frame.feet ? LEGS.map((leg) => frame.feet[leg]).filter((f) => f.contact) : [];
    const hull = convexHull(down.map((f) => f.position.slice(0, 2)));
    const z = down.length ? down.reduce((sum, f) => sum + f.position[2], 0) / down.length + 0.006 : 0;
    polygon.visible = edge.visible = hull.length >= 3;
    if (polygon.visible) {
      const corners = hull.map(([x, y]) => new THREE.Vector3(x, y, z));
      const positions = [];
      for (let i = 1; i + 1 < corners.length; i++) positions.push(...corners[0].toArray(), ...corners[i].toArray(), ...corners[i + 1].toArray());
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
      edge.geometry.setFromPoints(corners);
    }
    cop.visible = Boolean(frame.cop) && down.length > 0;
    if (cop.visible) cop.position.set(frame.cop[0], frame.cop[1], z + 0.003);
  };
  return group;
}

/** The footholds: one disc per new contact, on its surface, in the leg's colour (unlit). */
function footholds() {
  const group = new THREE.Group();
  const geometry = new THREE.CylinderGeometry(0.032, 0.032, 0.004, 28);
  const materials = Object.fromEntries(LEGS.map((leg) => [leg, new THREE.MeshBasicMaterial({ color: LEG_COLORS[leg] })]));
  const up = new THREE.Vector3(0, 1, 0);
  const seen = new Set();
  for (const s of drawnStates()) {
    for (const f of s.feet) {
      const key = `${f.leg}:${f.position.map((x) => x.toFixed(3)).join(',')}`;
      if (seen.has(key)) continue;
      seen.add(key);
      const normal = v3(f.normal).normalize();
      const disc = new THREE.Mesh(geometry, materials[f.leg]);
      disc.quaternion.setFromUnitVectors(up, normal);
      // Legs at different heights, so discs of two legs on one spot do not z-fight.
      disc.position.copy(v3(f.position).addScaledVector(normal, 0.007 + 0.0015 * LEGS.indexOf(f.leg)));
      group.add(disc);
    }
  }
  return group;
}

function shapeMesh(shape, material) {
  let geometry;
  if (shape.kind === 'box') geometry = new THREE.BoxGeometry(...shape.size);
  else if (shape.kind === 'sphere') geometry = new THREE.SphereGeometry(shape.radius, 20, 14);
  else geometry = new THREE.CylinderGeometry(shape.radius, shape.radius, shape.length, 24).rotateX(Math.PI / 2);  // URDF: axis z
  const mesh = new THREE.Mesh(geometry, material);
  mesh.position.fromArray(shape.origin.xyz);
  mesh.quaternion.fromArray(shape.origin.quaternion);
  mesh.castShadow = true;
  return mesh;
}

/** The robot: one group per URDF link holding its collision primitives, posed by FK. */
function buildRobot() {
  const root = new THREE.Group();
  root.matrixAutoUpdate = false;
  const material = (color) => new THREE.MeshStandardMaterial({ color, roughness: 0.55, metalness: 0.1 });
  const trunk = material(COLORS.trunk);
  const actuator = material(COLORS.actuator);
  const legMaterial = material(COLORS.leg);
  const links = new Map();
  const legOf = new Map(robot.links.map((l) => [l.name, l.leg]));
  for (const link of robot.links) {
    const group = new THREE.Group();
    group.matrixAutoUpdate = false;
    links.set(link.name, group);
    root.add(group);
  }
  const footMaterials = {};
  for (const shape of robot.shapes) {
    const leg = legOf.get(shape.link);
    let m = legMaterial;
    if (shape.kind === 'sphere' && leg) m = footMaterials[leg] ??= material(LEG_COLORS[leg]);
    else if (!leg) m = shape.kind === 'box' ? trunk : actuator;
    links.get(shape.link).add(shapeMesh(shape, m));
  }
  // Without joint angles (a trace without joints) the legs are drawn as hip-to-foot rods.
  const rods = new THREE.Group();
  const rodGeometry = new THREE.CylinderGeometry(0.016, 0.016, 1, 12);
  const footGeometry = new THREE.SphereGeometry(robot.foot_radius, 20, 14);
  const hips = hipPositions(robot);
  const rodParts = {};
  for (const leg of LEGS) {
    const rod = new THREE.Mesh(rodGeometry, legMaterial);
    const footMaterial = material(LEG_COLORS[leg]);
    const foot = new THREE.Mesh(footGeometry, footMaterial);
    rod.castShadow = foot.castShadow = true;
    rods.add(rod, foot);
    rodParts[leg] = { rod, foot, footMaterial };
  }
  const up = new THREE.Vector3(0, 1, 0);
  const showContact = (m, contact) => {
    m.emissive.set(contact ? '#000000' : '#555555');
    m.opacity = contact ? 1 : 0.55;
    m.transparent = !contact;
  };

  return {
    root,
    rods,
    /** Poses the robot at a frame of a track. */
    show(frame) {
      const base = baseMatrix(frame);
      root.matrix.copy(base);
      root.matrixWorldNeedsUpdate = true;
      const poses = frame.joints ? linkPoses(robot, frame.joints) : null;
      for (const [name, group] of links) {
        group.visible = Boolean(poses) || !legOf.get(name);
        if (poses) group.matrix.copy(poses.get(name));
      }
      if (poses && frame.feet) for (const leg of LEGS) if (footMaterials[leg]) showContact(footMaterials[leg], frame.feet[leg].contact);
      rods.visible = !poses && Boolean(frame.feet);
      if (!poses && frame.feet) {
        for (const leg of LEGS) {
          const hip = hips[leg].clone().applyMatrix4(base);
          const contact = v3(frame.feet[leg].position);
          const { rod, foot, footMaterial } = rodParts[leg];
          // The trace gives the contact point; the sphere's centre sits one radius above it.
          const centre = contact.clone().add(new THREE.Vector3(0, 0, robot.foot_radius));
          const axis = centre.clone().sub(hip);
          rod.position.copy(hip).addScaledVector(axis, 0.5);
          rod.scale.set(1, axis.length(), 1);
          rod.quaternion.setFromUnitVectors(up, axis.clone().normalize());
          foot.position.copy(centre);
          showContact(footMaterial, frame.feet[leg].contact);
        }
      }
    },
  };
}

function startGoalMarkers() {
  const group = new THREE.Group();
  for (const [pose, color] of [[sceneData.start, '#444444'], [sceneData.goal, '#111111']]) {
    if (!pose) continue;
    const [x, y] = pose.position;
    const z = groundBelow(x, y);
    const dir = new THREE.Vector3(Math.cos(pose.yaw), Math.sin(pose.yaw), 0);
    group.add(new THREE.ArrowHelper(dir, new THREE.Vector3(x, y, z + 0.01), 0.3, color, 0.08, 0.05));
  }
  return group;
}

/** Highest terrain point below (x, y), by a downward ray. */
function groundBelow(x, y) {
  const terrain = layers.terrain && layers.terrain.children[0];
  if (!terrain) return 0;
  const ray = new THREE.Raycaster(new THREE.Vector3(x, y, 100), new THREE.Vector3(0, 0, -1));
  const hit = ray.intersectObject(terrain, true)[0];
  return hit ? hit.point.z : 0;
}

/** The layers made from the world (terrain, surfaces, start and goal; a perceived run's
 *  elevation map and true terrain). */
function buildWorldLayers() {
  setLayerObject('terrain', terrainMesh());
  setLayerObject('surfaces', surfaceMeshes());
  setLayerObject('markers', startGoalMarkers());
  if (perception && perception.elevation_map) setLayerObject('elevation', elevationTiles());
  if (perception && perception.true_terrain) setLayerObject('truth', trueTerrain());
}

/** The layers made from the run (root path, footholds, and those of the trace). */
function buildRunLayers() {
  setLayerObject('footholds', footholds());
  setLayerObject('path', rootPath());
  buildTraceLayers();
}

/** The layers made from the trace: walked path, references, support polygon and CoP. */
function buildTraceLayers() {
  setLayerObject('simpath', simPath());
  const balance = traceBalance();
  if (balance.references) setLayerObject('references', referenceTrails());
  if (balance.cop && !layers.support) setLayerObject('support', supportView());
}

function setupScene() {
  const canvas = $('view');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
  } catch (error) {
    $('viewport').classList.add('no-webgl');
    $('webgl-message').textContent = `3D view unavailable: ${error.message}`;
    return null;
  }
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE.PCFShadowMap;
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(COLORS.background);
  const robotView = buildRobot();
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 200);
  camera.up.set(0, 0, 1);
  const controls = new OrbitControls(camera, canvas);
  controls.enableDamping = true;
  scene.add(new THREE.HemisphereLight('#ffffff', '#8a7f6a', 1.6));
  const sun = new THREE.DirectionalLight('#ffffff', 2.2);
  sun.castShadow = true;
  sun.shadow.mapSize.set(2048, 2048);
  scene.add(sun, sun.target);

  // What the camera frames: the path, the footholds and the trace with a margin for the robot,
  // within the terrain's extent (the whole terrain when there is no path; for a perceived run
  // the true terrain's too: its map is the last one, which may no longer hold the start).
  const home = () => {
    const terrainBox = layers.terrain ? new THREE.Box3().setFromObject(layers.terrain) : new THREE.Box3();
    if (layers.truth) terrainBox.union(new THREE.Box3().setFromObject(layers.truth));
    const focus = new THREE.Box3();
    for (const p of run.root_path || []) focus.expandByPoint(v3(p.position));
    for (const s of drawnStates()) for (const f of s.feet) focus.expandByPoint(v3(f.position));
    for (const s of run.sim_trace || []) focus.expandByPoint(v3(s.base.position));
    if (focus.isEmpty()) focus.copy(terrainBox);
    else if (!terrainBox.isEmpty()) {
      focus.expandByVector(new THREE.Vector3(0.7, 0.7, 0.3));
      focus.min.z = Math.max(focus.min.z, terrainBox.min.z);
      focus.intersect(terrainBox.clone().expandByVector(new THREE.Vector3(0, 0, 1)));
      if (focus.isEmpty()) focus.copy(terrainBox);
    } else {
      focus.expandByVector(new THREE.Vector3(0.7, 0.7, 0.3));
    }
    if (focus.isEmpty()) focus.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 0.5));
    const sphere = focus.getBoundingSphere(new THREE.Sphere());
    const direction = new THREE.Vector3(-0.55, -1.0, 0.72).normalize();
    const distance = (sphere.radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2))) * 0.72;
    controls.target.copy(sphere.center);
    camera.position.copy(sphere.center).addScaledVector(direction, distance);
    controls.update();
    sun.position.copy(sphere.center).add(new THREE.Vector3(-2, -3, 6));
    sun.target.position.copy(sphere.center);
    const r = sphere.radius * 1.3;
    Object.assign(sun.shadow.camera, { left: -r, right: r, top: r, bottom: -r, near: 0.1, far: 30 });
    sun.shadow.camera.updateProjectionMatrix();
    invalidate();
  };

  const resize = () => {
    const { clientWidth: w, clientHeight: h } = canvas.parentElement;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    invalidate();
  };
  new ResizeObserver(resize).observe(canvas.parentElement);
  resize();
  return { renderer, scene, camera, controls, robotView, home };
}

// ---- Plots ---------------------------------------------------------------------------------------

/** Intervals [a, b] where flags[i] holds, for samples at times ts. */
function intervals(ts, flags) {
  const out = [];
  let start = null;
  for (let i = 0; i < ts.length; i++) {
    if (flags[i] && start === null) start = ts[i];
    if (!flags[i] && start !== null) {
      out.push([start, ts[i]]);
      start = null;
    }
  }
  if (start !== null) out.push([start, ts[ts.length - 1]]);
  return out;
}

/** Signed distance [m] of a trace frame's centre of pressure inside the polygon of its feet in
 *  contact (positive inside); NaN without a CoP or with fewer than three feet down. */
function copMargin(frame) {
  if (!frame.cop) return NaN;
  const down = LEGS.map((leg) => frame.feet[leg]).filter((f) => f.contact);
  return polygonMargin(convexHull(down.map((f) => f.position.slice(0, 2))), frame.cop);
}

/** A trace's margins in the polygon of the feet in contact: the CoM's, and the CoP's when the
 *  trace carries it. */
function balancePlots(add, frames, xLabel, xRange) {
  const edge = { y: 0, color: COLORS.limit, label: 'edge' };
  if (frames.some((f) => f.margin !== null)) {
    const required = robot.support_margin_m;
    add(linePlot, {
      title: 'CoM margin in the polygon of the feet in contact', yLabel: '[m]', xLabel, xRange,
      hlines: [edge, ...(required ? [{ y: required, color: '#888', label: `controller's ${required} m` }] : [])],
      series: [{ name: 'margin', color: '#2e7d32', points: frames.map((f) => [f.t, f.margin ?? NaN]) }],
    });
  }
  if (frames.some((f) => f.cop)) {
    add(linePlot, {
      title: 'CoP margin in the polygon of the feet in contact', yLabel: '[m]', xLabel, xRange, hlines: [edge],
      series: [{ name: 'CoP margin', color: COLORS.cop, points: frames.map((f) => [f.t, copMargin(f)]) }],
    });
  }
}

function buildPlots(track) {
  const box = $('plots');
  box.replaceChildren();
  const plots = [];
  const add = (make, options) => {
    const div = document.createElement('div');
    box.appendChild(div);
    const plot = make(div, options);
    plot.onSeek((t) => {
      liveFollow = false;
      setTime(t);
    });
    plots.push(plot);
  };
  const frames = track.frames;
  const xRange = [frames[0].t, Math.max(track.duration, frames[0].t + 1e-6)];
  const xLabel = track.kind === 'plan' ? 'plan state' : 'time [s]';
  const deg = (r) => (r * 180) / Math.PI;
  const progress = () => add(linePlot, {
    title: 'base position', yLabel: 'x, y [m]', xLabel, xRange,
    series: [
      { name: 'x', color: '#6a3d9a', points: frames.map((f) => [f.t, f.position[0]]) },
      { name: 'y', color: '#b15928', points: frames.map((f) => [f.t, f.position[1]]) },
    ],
  });
  if (track.kind === 'root') {
    add(linePlot, {
      title: 'base height', yLabel: 'z [m]', xLabel, xRange,
      series: [{ name: 'z', color: '#333', points: frames.map((f) => [f.t, f.position[2]]) }],
    });
    add(linePlot, {
      title: 'heading', yLabel: 'yaw [deg]', xLabel, xRange,
      series: [{ name: 'yaw', color: '#333', points: frames.map((f) => [f.t, deg(f.rpy[2])]) }],
    });
    progress();
    return plots;
  }

  // The step timeline: per leg, filled while the foot stands.
  let rows;
  if (track.kind === 'plan') {
    // Between states i-1 and i the moving leg of state i swings; the others stand.
    rows = LEGS.map((leg) => {
      const flags = frames.map((f, i) => !(frames[i + 1] && frames[i + 1].moving_leg === leg));
      return { name: leg, color: LEG_COLORS[leg], intervals: intervals(frames.map((f) => f.t), flags) };
    });
  } else {
    const ts = frames.map((f) => f.t);
    rows = LEGS.map((leg) => ({ name: leg, color: LEG_COLORS[leg], intervals: intervals(ts, frames.map((f) => f.feet[leg].contact)) }));
  }
  add(ganttPlot, { title: 'step timeline per leg (filled: foot in contact)', xLabel, xRange, rows });

  if (track.kind === 'sim' && frames.some((f) => f.torques)) {
    const limit = robot.torque_limit_Nm;
    const hlines = limit ? [{ y: limit, color: COLORS.limit, label: `limit ${limit} N m` }, { y: -limit, color: COLORS.limit }] : [];
    JOINT_KINDS.forEach((kind, j) => add(linePlot, {
      title: `${kind} joint torques`, yLabel: 'τ [N m]', xLabel, xRange, hlines, height: 130,
      series: LEGS.map((leg, l) => ({
        name: `${leg}_${kind}`, color: LEG_COLORS[leg], points: frames.map((f) => [f.t, f.torques ? f.torques[3 * l + j] : NaN]),
      })),
    }));
  }
  if (track.kind === 'sim') balancePlots(add, frames, xLabel, xRange);
  if (track.kind === 'sim' && (run.replans || []).length) {
    add(linePlot, {
      title: `replanning latency (${run.replans.length} replans)`, yLabel: '[ms]', xLabel, xRange,
      series: [{ name: 'latency', color: '#6a3d9a', markers: true, points: run.replans.map((r) => [r.t, r.latency_ms]) }],
    });
  }
  add(linePlot, {
    title: 'base height', yLabel: 'z [m]', xLabel, xRange,
    series: [{ name: 'z', color: '#333', points: frames.map((f) => [f.t, f.position[2]]) }],
  });
  add(linePlot, {
    title: 'base roll and pitch', yLabel: '[deg]', xLabel, xRange,
    series: [
      { name: 'roll', color: '#d62728', points: frames.map((f) => [f.t, deg(f.rpy[0])]) },
      { name: 'pitch', color: '#1f77b4', points: frames.map((f) => [f.t, deg(f.rpy[1])]) },
    ],
  });
  if (track.kind === 'sim') {
    // Steps walked: touchdowns that end a swing (contact lost, then regained), all legs.
    let count = 0;
    const lifted = {};
    const points = frames.map((f, i) => {
      for (const leg of LEGS) {
        const before = i > 0 && frames[i - 1].feet[leg].contact;
        if (before && !f.feet[leg].contact) lifted[leg] = true;
        if (!before && f.feet[leg].contact && lifted[leg]) {
          count += 1;
          lifted[leg] = false;
        }
      }
      return [f.t, count];
    });
    const total = run.steps_total ?? run.steps;
    add(linePlot, {
      title: `steps walked (touchdowns after a swing)${total !== undefined ? `, plan ${total}` : ''}`,
      xLabel, xRange, series: [{ name: 'steps', color: '#333', points, step: true }],
    });
  } else {
    progress();
  }
  return plots;
}

// ---- Playback ------------------------------------------------------------------------------------

const view = setupScene();
let track = null;
let plots = [];
let time = 0;
let playing = false;
let follow = null;  // base position last followed, when following
let liveFollow = Boolean(data.live);  // live: the robot shown is the newest state

function setTime(t) {
  if (!track) return;
  time = Math.min(Math.max(t, 0), track.duration);
  const frame = track.at(time);
  invalidate();
  if (view) {
    view.robotView.show(frame);
    if (layers.support) layers.support.userData.show(track.kind === 'sim' ? frame : {});
    if (follow) {
      const p = v3(frame.position);
      const delta = p.clone().sub(follow);
      view.camera.position.add(delta);
      view.controls.target.add(delta);
      follow = p;
    }
  }
  $('slider').value = time;
  for (const plot of plots) plot.setCursor(time);
  if (track.kind === 'plan') {
    const states = run.states;
    const i = Math.floor(time + 1e-9);
    const text = time - i > 1e-9
      ? `${states[i + 1].moving_leg} steps from state ${i} to ${i + 1}`
      : `state ${i}${states[i].moving_leg ? `, reached by moving ${states[i].moving_leg}` : ' (start)'}`;
    $('clock').textContent = `${time.toFixed(2)} / ${track.duration} · ${text}`;
  } else if (track.kind === 'root') {
    $('clock').textContent = `t ${time.toFixed(2)} s / ${track.duration.toFixed(2)} s · planned trunk path (no legs)`;
  } else {
    const contacts = LEGS.filter((leg) => frame.feet[leg].contact).join(' ') || 'none';
    $('clock').textContent = `t ${time.toFixed(2)} s / ${track.duration.toFixed(2)} s · in contact: ${contacts}`;
  }
}

function setPlaying(on) {
  playing = on && Boolean(track);
  if (playing && time >= track.duration) time = 0;
  if (playing) liveFollow = false;
  $('play').textContent = playing ? '❚❚ Pause' : '▶ Play';
}

function selectTrack(kind) {
  track = tracks[kind];
  $('slider').max = track.duration;
  $('slider').step = track.kind === 'plan' ? 0.01 : 0.05;
  plots = buildPlots(track);
  setTime(liveFollow ? track.duration : Math.min(time, track.duration));
}

function fillTrackSelect() {
  const select = $('track');
  const current = select.value;
  select.replaceChildren();
  for (const [kind, label] of [['sim', data.live ? 'live run' : 'simulated run'], ['plan', 'contact plan'], ['root', 'root path']]) {
    if (tracks[kind]) select.add(new Option(`${label} (${tracks[kind].frames.length} ${kind === 'plan' ? 'states' : 'samples'})`, kind));
  }
  if (tracks[current]) select.value = current;
}

function setControlsEnabled(on) {
  $('controls').classList.toggle('disabled', !on);
  for (const el of $('controls').querySelectorAll('button:not(#home), input, select')) el.disabled = !on;
  if (layers.robot) layers.robot.visible = on && !hidden.has('robot');
  invalidate();
}

function setupControls() {
  const select = $('track');
  select.addEventListener('change', () => selectTrack(select.value));
  $('play').addEventListener('click', () => setPlaying(!playing));
  $('slider').addEventListener('input', (e) => {
    liveFollow = false;
    setTime(Number(e.target.value));
  });
  $('home').addEventListener('click', () => view && view.home());
  $('follow').addEventListener('change', (e) => {
    follow = e.target.checked && track ? v3(track.at(time).position) : null;
  });
  if (data.live) {
    const latest = $('latest');
    latest.hidden = false;
    latest.addEventListener('click', () => {
      setPlaying(false);
      liveFollow = true;
      if (track) setTime(track.duration);
    });
  }
  for (const box of document.querySelectorAll('#layers input')) {
    box.addEventListener('change', () => setLayer(box.dataset.layer, box.checked));
    if (!layers[box.dataset.layer] && view) box.closest('label').hidden = true;
  }
  window.addEventListener('keydown', (e) => {
    if (!track || e.target.tagName === 'SELECT') return;
    const step = track.kind === 'plan' ? 1 : 0.5;
    if (e.key === ' ') setPlaying(!playing);
    else if (e.key === 'ArrowRight') setTime(time + step);
    else if (e.key === 'ArrowLeft') setTime(time - step);
    else return;
    liveFollow = false;
    e.preventDefault();
  });
}

/** (Re)builds the tracks and, when the track shown changes or grows, the timeline and plots. */
function refreshTracks() {
  buildTracks();
  fillTrackSelect();
  const kind = track && tracks[track.kind] ? track.kind : ['sim', 'plan', 'root'].find((k) => tracks[k]);
  if (!kind) {
    track = null;
    setControlsEnabled(false);
    $('clock').textContent = data.live
      ? 'waiting for the robot (ROBOT_STATE)'
      : 'nothing to play: the input has no plan states, simulated trace or root path';
    $('plots').textContent = data.live ? 'The plots fill as the run goes.' : 'The input has no time series to plot.';
    return;
  }
  setControlsEnabled(true);
  $('track').value = kind;
  selectTrack(kind);
}

function setLayer(name, visible) {
  if (visible) hidden.delete(name);
  else hidden.add(name);
  if (layers[name]) layers[name].visible = visible;
  invalidate();
}

if (view) {
  buildWorldLayers();
  buildRunLayers();
  const robotGroup = setLayerObject('robot', new THREE.Group());
  robotGroup.add(view.robotView.root, view.robotView.rods);
  view.home();
}
renderHeader();
renderLegend();
renderSummary();
renderPerception();
setupControls();
refreshTracks();

// ---- Live: the run grows as messages come --------------------------------------------------------

const liveState = { connected: false, messages: {}, processes: {}, lastT: null, verdict: null };
if (data.live) {
  let dirtyWorld = false;
  let dirtyRun = false;
  let dirtyTrack = false;
  let homed = false;
  const trace = (run.sim_trace = []);
  run.states = [];
  run.plan_ahead = [];
  run.replans = [];
  const renderLiveStatus = () => {
    const procs = Object.values(liveState.processes)
      .map((p) => `${p.process} ${p.state}${p.state === 'failed' && p.reason ? ` (${p.reason})` : ''}`).join(' · ');
    const t = liveState.lastT === null ? '' : ` · t ${liveState.lastT.toFixed(1)} s`;
    if (liveState.verdict) {
      setStatus(liveState.verdict.ok ? 'ok' : 'failed', `live: ${liveState.verdict.text}${t}`);
    } else {
      setStatus(liveState.connected ? 'ok' : 'neutral', `${liveState.connected ? 'live' : `connecting to ${liveUrl}`}${t}`);
    }
    $('source').textContent = `live from ${liveUrl}${procs ? ` · ${procs}` : ''}`;
  };
  connectLive(liveUrl, {
    open() {
      liveState.connected = true;
      renderLiveStatus();
    },
    close() {
      liveState.connected = false;
      renderLiveStatus();
    },
    message(m) {
      liveState.messages[m.type] = (liveState.messages[m.type] || 0) + 1;
      if (m.type === 'terrain') {
        sceneData.terrain = { vertices: m.vertices, triangles: m.triangles };
        if (m.scenario) run.scenario = m.scenario;
        dirtyWorld = true;
      } else if (m.type === 'surfaces') {
        sceneData.contact_surfaces = m.contact_surfaces;
        dirtyWorld = true;
      } else if (m.type === 'request') {
        sceneData.goal = m.goal;
        dirtyWorld = true;
      } else if (m.type === 'root_path') {
        run.root_path = m.root_path;
        dirtyRun = true;
      } else if (m.type === 'plan') {
        run.plan_ahead = m.states;
        dirtyRun = true;
      } else if (m.type === 'walked') {
        run.states = m.states;
        dirtyRun = true;
      } else if (m.type === 'state') {
        if (trace.length && m.t < trace[trace.length - 1].t) trace.length = 0;  // a new run
        trace.push(m);
        if (!sceneData.start) sceneData.start = { position: m.base.position.slice(0, 2), yaw: m.base.rpy[2] };
        liveState.lastT = m.t;
        run.steps = m.steps_done;
        dirtyTrack = true;
      } else if (m.type === 'replan') {
        run.replans.push({ t: m.t, latency_ms: m.latency_ms });
      } else if (m.type === 'status') {
        liveState.processes[m.process] = m;
        if (m.process === 'anymal_sim' && (m.state === 'ok' || m.state === 'failed') && m.reason) {
          liveState.verdict = { ok: m.state === 'ok', text: m.reason };
        }
      }
      renderLiveStatus();
    },
  });
  // Rebuild what changed a few times a second; plots once a second.
  let lastPlots = 0;
  setInterval(() => {
    if (!view) return;
    if (dirtyWorld) {
      buildWorldLayers();
      renderSummary();
      dirtyWorld = false;
    }
    if (dirtyRun) {
      setLayerObject('footholds', footholds());
      setLayerObject('path', rootPath());
      dirtyRun = false;
    }
    const now = performance.now();
    if (dirtyTrack && now - lastPlots > 1000) {
      buildTraceLayers();
      renderLegend();
      refreshTracks();
      lastPlots = now;
      dirtyTrack = false;
    } else if (dirtyTrack && track && track.kind === 'sim') {
      // Between plot updates the robot still follows the newest state.
      const newest = traceFrame(trace[trace.length - 1], trace.length - 1);
      if (liveFollow) {
        view.robotView.show(newest);
        if (layers.support) layers.support.userData.show(newest);
        invalidate();
      }
    }
    if (!homed && sceneData.terrain && trace.length) {
      view.home();
      homed = true;
    }
  }, 200);
}

// ---- Render loop ---------------------------------------------------------------------------------

let last = performance.now();
let frames = 0;
function tick(now) {
  const dt = Math.min((now - last) / 1000, 0.1);
  last = now;
  if (playing) {
    // Plans play one state per second at 1x, traces in real time.
    const t = time + dt * Number($('speed').value);
    setTime(t);
    if (t >= track.duration) setPlaying(false);
  }
  if (view) {
    if (view.controls.update()) dirty = true;  // the camera moved (or glides on)
    if (dirty) {
      dirty = false;
      view.renderer.render(view.scene, view.camera);
    }
  }
  frames += 1;
  if (frames === 2) window.rbcpViewer.ready = true;
  requestAnimationFrame(tick);
}

window.rbcpViewer = {
  ready: false,
  webgl: Boolean(view),
  checks: data.checks,
  get tracks() {
    return Object.keys(tracks);
  },
  get layers() {
    return Object.keys(layers);
  },
  /** The current track's duration (s, or plan states). */
  get duration() {
    return track ? track.duration : 0;
  },
  live: data.live ? liveState : null,
  /** Shows the newest live state, or time t of the current track. */
  setTime,
  setLayer,
  selectTrack,
  home: () => view && view.home(),
};
requestAnimationFrame(tick);
