// Shrinks a run_log JSON of a run on the mapped terrain (--terrain perceived) into a small test
// input for the viewer: the elevation map and the mapped terrain cropped to the cells within
// MARGIN of the walked base path, every EVERY-th trace sample kept (the last one too), numbers
// rounded to 1e-6 (the map's heights to 0.1 mm). The perception metrics stay the whole run's.
//
//   node crop_run.mjs --run RUN.json [--margin 0.8] [--every 2] -o OUT.json
import { readFileSync, writeFileSync } from 'node:fs';
import { parseArgs } from 'node:util';

const USAGE = 'usage: node crop_run.mjs --run RUN.json [--margin M] [--every N] -o OUT.json';
let args;
try {
  ({ values: args } = parseArgs({
    options: {
      run: { type: 'string' }, output: { type: 'string', short: 'o' },
      margin: { type: 'string', default: '0.8' }, every: { type: 'string', default: '2' },
    },
  }));
} catch (error) {
  console.error(`crop_run: ${error.message}\n${USAGE}`);
  process.exit(2);
}
const margin = Number(args.margin);
const every = Number(args.every);
if (!args.run || !args.output || !(margin >= 0) || !(Number.isInteger(every) && every >= 1)) {
  console.error(USAGE);
  process.exit(2);
}
const run = JSON.parse(readFileSync(args.run, 'utf8'));
const map = run.perception && run.perception.elevation_map;
if (!map || !(run.sim_trace || []).length) {
  console.error(`crop_run: ${args.run} has no elevation map or no trace (not a perceived run's run_log JSON)`);
  process.exit(1);
}

// The box around the walked path.
const xs = run.sim_trace.map((s) => s.base.position[0]);
const ys = run.sim_trace.map((s) => s.base.position[1]);
const box = [Math.min(...xs) - margin, Math.min(...ys) - margin, Math.max(...xs) + margin, Math.max(...ys) + margin];
const inside = (p) => p[0] >= box[0] && p[0] <= box[2] && p[1] >= box[1] && p[1] <= box[3];

// The map's cells in the box.
const r = map.resolution;
const clamp = (v, n) => Math.min(Math.max(v, 0), n);
const [ix0, iy0] = [clamp(Math.floor((box[0] - map.origin[0]) / r), map.num_x), clamp(Math.floor((box[1] - map.origin[1]) / r), map.num_y)];
const [ix1, iy1] = [clamp(Math.ceil((box[2] - map.origin[0]) / r), map.num_x), clamp(Math.ceil((box[3] - map.origin[1]) / r), map.num_y)];
const height = [];
for (let iy = iy0; iy < iy1; iy++) {
  for (let ix = ix0; ix < ix1; ix++) {
    const h = map.height[iy * map.num_x + ix];
    height.push(h === null ? null : Math.round(h * 1e4) / 1e4);
  }
}
run.perception.elevation_map = {
  ...map, origin: [map.origin[0] + ix0 * r, map.origin[1] + iy0 * r], num_x: ix1 - ix0, num_y: iy1 - iy0, height,
};

// The mapped terrain: the triangles with every corner in the box.
if (run.terrain) {
  const keep = run.terrain.triangles.filter((t) => t.every((i) => inside(run.terrain.vertices[i])));
  const renumber = new Map();
  const vertices = [];
  const triangles = keep.map((t) => t.map((i) => {
    if (!renumber.has(i)) {
      renumber.set(i, vertices.length);
      vertices.push(run.terrain.vertices[i]);
    }
    return renumber.get(i);
  }));
  run.terrain = { vertices, triangles };
}
if (run.contact_surfaces) run.contact_surfaces = run.contact_surfaces.filter((s) => s.vertices.every(inside));
run.surfaces = (run.contact_surfaces || []).length;

run.sim_trace = run.sim_trace.filter((s, i, all) => i % every === 0 || i === all.length - 1);
const text = JSON.stringify(run, (key, v) => (typeof v === 'number' && !Number.isInteger(v) ? Math.round(v * 1e6) / 1e6 : v));
writeFileSync(args.output, text);
const kb = (Buffer.byteLength(text) / 1024).toFixed(0);
console.error(`crop_run: wrote ${args.output} (${kb} KiB; map ${ix1 - ix0} x ${iy1 - iy0} cells, ` +
  `${run.terrain ? run.terrain.triangles.length : 0} terrain triangles, ${run.sim_trace.length} trace samples)`);
