// Assembles the viewer page: the template, three.js and the viewer's modules inlined as text,
// and the data (a plan_scenario or run_log JSON and a scene_json JSON) in one self-contained HTML
// file. Checks the page's forward kinematics against rbcp::RobotModel (scene_json's reference link
// poses) and against the plan's foot positions before writing anything. A live page (--live-port)
// has no run: it connects to live_bridge's websocket and fills as the run goes.
//
//   node assemble.mjs --plan PLAN.json --scene SCENE.json -o OUT.html [--name SHOWN_NAME]
//   node assemble.mjs --live-port PORT --scene ROBOT.json -o OUT.html
import { readFileSync, writeFileSync } from 'node:fs';
import { basename, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { REVISION, Vector3 } from 'three';

import { baseMatrix, footContacts, linkPoses, poseMatrix } from './src/kinematics.js';

const here = dirname(fileURLToPath(import.meta.url));
const three = join(here, 'node_modules', 'three');

function fail(message) {
  console.error(`view: ${message}`);
  process.exit(1);
}

function readJson(path, what) {
  let text;
  try {
    text = readFileSync(path, 'utf8');
  } catch (error) {
    fail(`cannot read the ${what} ${path}: ${error.message}`);
  }
  try {
    return JSON.parse(text);
  } catch (error) {
    fail(`${path} is not JSON (${error.message})`);
  }
}

/** Largest element difference between the viewer's FK and rbcp::RobotModel's link poses at the
 *  reference stance (rotation entries and translations [m]). */
function referenceError(robot) {
  const poses = linkPoses(robot, robot.reference_configuration);
  let worst = 0;
  for (const [name, expected] of Object.entries(robot.reference_link_poses)) {
    const got = poses.get(name);
    if (!got) fail(`kinematics: link ${name} is not reached by the joint tree`);
    const want = poseMatrix(expected).elements;
    got.elements.forEach((v, i) => (worst = Math.max(worst, Math.abs(v - want[i]))));
  }
  return worst;
}

/** Largest distance between the plan's foot positions and FK of its base pose and joints. */
function feetError(robot, states) {
  let worst = null;
  for (const state of states) {
    const world = baseMatrix(state.base);
    const feet = footContacts(robot, linkPoses(robot, state.joints));
    for (const foot of state.feet) {
      const p = feet[foot.leg].clone().applyMatrix4(world);
      worst = Math.max(worst ?? 0, p.distanceTo(new Vector3(...foot.position)));
    }
  }
  return worst;
}

function moduleSource(path) {
  return readFileSync(path, 'utf8');
}

/** A <script type="text/plain"> holding a module's source; refuses text that would end it early. */
function inlineModule(name, source) {
  if (/<\/script|<!--/i.test(source)) fail(`module ${name} contains '</script' or '<!--' and cannot be inlined`);
  return `<script type="text/plain" data-module="${name}">\n${source}\n</script>`;
}

function main() {
  let args;
  try {
    args = parseArgs({
      options: {
        plan: { type: 'string' }, scene: { type: 'string' }, output: { type: 'string', short: 'o' },
        'live-port': { type: 'string' }, name: { type: 'string' },
      },
    }).values;
  } catch (error) {
    console.error(`view: ${error.message}`);
    process.exit(2);
  }
  const live = args['live-port'] !== undefined;
  if ((!args.plan && !live) || (args.plan && live) || !args.scene || !args.output) {
    console.error('usage: node assemble.mjs --plan PLAN.json --scene SCENE.json -o OUT.html\n' +
                  '       node assemble.mjs --live-port PORT --scene ROBOT.json -o OUT.html');
    process.exit(2);
  }
  const port = Number(args['live-port']);
  if (live && !(Number.isInteger(port) && port > 0 && port < 65536)) fail(`--live-port: expected a port number, got '${args['live-port']}'`);
  const run = live ? {} : readJson(args.plan, 'plan');
  const scene = readJson(args.scene, 'scene');
  if (typeof run !== 'object' || run === null || Array.isArray(run)) fail(`${args.plan}: expected a JSON object`);
  if (!('robot' in scene)) fail(`${args.scene}: no 'robot'`);
  // A run's log (run_log) brings its own world: the terrain, surfaces, start and goal it saw.
  for (const key of ['terrain', 'contact_surfaces', 'start', 'goal']) {
    if (!(key in scene) && run[key]) scene[key] = run[key];
    delete run[key];
  }
  if (!live) for (const key of ['terrain', 'contact_surfaces']) if (!(key in scene)) fail(`${args.scene}: no '${key}' (and the run has none)`);
  if (run.scenario && scene.scenario && run.scenario !== scene.scenario) {
    console.error(`view: warning: the plan is for scenario '${run.scenario}', the scene is '${scene.scenario}'`);
  }
  const states = Array.isArray(run.states) ? run.states : [];

  const referenceErr = referenceError(scene.robot);
  if (!(referenceErr < 1e-9)) fail(`kinematics: the viewer's FK is ${referenceErr} m off rbcp::RobotModel at the reference stance`);
  const feetErr = feetError(scene.robot, states);
  if (feetErr !== null && feetErr > 1e-3) {
    console.error(`view: warning: plan feet are up to ${feetErr.toFixed(4)} m from the FK of their states`);
  }

  let threeModule = moduleSource(join(three, 'build', 'three.module.js'));
  // three.module.js imports its core by a relative path, which blob: URLs cannot resolve.
  const coreImport = /(from\s*)'\.\/three\.core\.js'/g;
  if (!coreImport.test(threeModule)) fail('three.module.js no longer imports ./three.core.js; update assemble.mjs');
  threeModule = threeModule.replace(coreImport, "$1'three/core'");
  const modules = [
    inlineModule('three/core', moduleSource(join(three, 'build', 'three.core.js'))),
    inlineModule('three', threeModule),
    inlineModule('three/addons/controls/OrbitControls.js', moduleSource(join(three, 'examples', 'jsm', 'controls', 'OrbitControls.js'))),
    inlineModule('viewer/kinematics.js', moduleSource(join(here, 'src', 'kinematics.js'))),
    inlineModule('viewer/plots.js', moduleSource(join(here, 'src', 'plots.js'))),
    inlineModule('viewer/support.js', moduleSource(join(here, 'src', 'support.js'))),
    inlineModule('viewer/live.js', moduleSource(join(here, 'src', 'live.js'))),
    inlineModule('viewer/main.js', moduleSource(join(here, 'src', 'main.js'))),
  ];

  const data = {
    run,
    scene,
    source: { plan: live ? null : args.name ?? basename(args.plan), scene: basename(args.scene) },
    checks: { reference_error: referenceErr, feet_error_m: feetErr },
  };
  if (live) data.live = { port };
  // '<' escaped so no string in the data can close the script element.
  const dataScript = `<script type="application/json" id="rbcp-data">${JSON.stringify(data).replace(/</g, '\\u003c')}</script>`;
  const title = String(run.scenario || scene.scenario || (live ? 'live' : 'plan')).replace(/[<&]/g, '');
  const network = live
    ? `the page connects only to live_bridge's websocket (port ${port}, or the host that serves it)`
    : 'the page makes no network request';
  const html = readFileSync(join(here, 'src', 'template.html'), 'utf8')
    .replace('@TITLE@', () => title)
    .replace('@THREE_REVISION@', () => REVISION)
    .replace('@NETWORK@', () => network)
    .replace('<!-- @MODULES@ -->', () => modules.join('\n'))
    .replace('<!-- @DATA@ -->', () => dataScript);
  writeFileSync(args.output, html);
  const kb = (Buffer.byteLength(html) / 1024).toFixed(0);
  const feet = live ? `live from port ${port}` : feetErr === null ? 'no plan states' : `plan feet within ${feetErr.toExponential(1)} m of FK`;
  console.error(`view: wrote ${args.output} (${kb} KiB; ${states.length} states, ${(run.sim_trace || []).length} trace samples; ${feet})`);
}

main();
