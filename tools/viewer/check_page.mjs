// Headless check of a viewer page in Debian's Chromium (driven by playwright-core): the page
// loads (from disk, or from live_bridge), makes no network request (a live page: none but to its
// bridge), logs no console error, draws with WebGL, and its screenshot shows the terrain, the
// footholds in the four leg colours and the robot. A live page must first have received the terrain, the walked
// steps and the robot's states, and the robot's time must move on. --expect-layer: the layer is
// drawn (hiding it changes pixels of the 3D view); --no-layer: the page has no such layer;
// --expect-perception: the perception panel (a run on the mapped terrain) is shown and says TEXT.
//
//   node check_page.mjs (--page PAGE.html | --url URL) --screenshot OUT.png [--expect-status TEXT]
//                       [--expect-plot TEXT]... [--expect-legend TEXT]... [--expect-layer NAME]...
//                       [--no-layer NAME]... [--expect-perception TEXT]... [--no-footholds] [--live]
//                       [--allow-host HOST:PORT]
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { parseArgs } from 'node:util';
import { inflateSync } from 'node:zlib';
import { chromium } from 'playwright-core';

const LEG_COLORS = { LF: [0xe4, 0x1a, 0x1c], RF: [0x33, 0xa0, 0x2c], LH: [0x1f, 0x78, 0xb4], RH: [0xff, 0xcc, 0x00] };
const CHROMIUM_FLAGS = [
  '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
];
const USAGE = 'usage: node check_page.mjs (--page PAGE.html | --url URL) --screenshot OUT.png [--expect-status TEXT]\n' +
  '                           [--expect-plot TEXT]... [--expect-legend TEXT]... [--expect-layer NAME]...\n' +
  '                           [--no-layer NAME]... [--expect-perception TEXT]... [--no-footholds] [--live]\n' +
  '                           [--allow-host HOST:PORT]';

let args;
try {
  ({ values: args } = parseArgs({
    options: {
      page: { type: 'string' },
      url: { type: 'string' },
      screenshot: { type: 'string' },
      'expect-status': { type: 'string' },
      'expect-plot': { type: 'string', multiple: true, default: [] },
      'expect-legend': { type: 'string', multiple: true, default: [] },
      'expect-layer': { type: 'string', multiple: true, default: [] },
      'no-layer': { type: 'string', multiple: true, default: [] },
      'expect-perception': { type: 'string', multiple: true, default: [] },
      'no-footholds': { type: 'boolean', default: false },
      live: { type: 'boolean', default: false },
      'allow-host': { type: 'string' },
      chromium: { type: 'string', default: '/usr/bin/chromium' },
    },
  }));
} catch (error) {
  console.error(`check_page: ${error.message}\n${USAGE}`);
  process.exit(2);
}
if (!(args.page || args.url) || (args.page && args.url) || !args.screenshot) {
  console.error(USAGE);
  process.exit(2);
}

/** Decodes an 8-bit RGB or RGBA, non-interlaced PNG (what Chromium writes) to RGBA rows. */
function decodePng(buffer) {
  let offset = 8;
  let width = 0;
  let height = 0;
  let channels = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('ascii', offset + 4, offset + 8);
    const body = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || body[12] !== 0 || (body[9] !== 2 && body[9] !== 6)) throw new Error('unsupported PNG format');
      channels = body[9] === 6 ? 4 : 3;
    } else if (type === 'IDAT') idat.push(body);
    offset += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = Buffer.alloc(width * height * 4);
  let previous = Buffer.alloc(stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = Buffer.from(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let i = 0; i < stride; i++) {
      const a = i >= channels ? line[i - channels] : 0;
      const b = previous[i];
      const c = i >= channels ? previous[i - channels] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a);
        const pb = Math.abs(p - b);
        const pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[i] = (line[i] + predictor) & 0xff;
    }
    for (let x = 0; x < width; x++) {
      for (let k = 0; k < 3; k++) pixels[(y * width + x) * 4 + k] = line[x * channels + k];
      pixels[(y * width + x) * 4 + 3] = channels === 4 ? line[x * channels + 3] : 255;
    }
    previous = line;
  }
  return { width, height, pixels };
}

/** Pixels of the box (CSS px = screenshot px at device scale 1) for which test(r, g, b, i) holds. */
function count(image, box, test) {
  let n = 0;
  for (let y = Math.ceil(box.y); y < Math.floor(box.y + box.height); y++) {
    for (let x = Math.ceil(box.x); x < Math.floor(box.x + box.width); x++) {
      const i = (y * image.width + x) * 4;
      if (test(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2], i)) n++;
    }
  }
  return n;
}

const near = (rgb, tolerance = 14) => (r, g, b) =>
  Math.abs(r - rgb[0]) <= tolerance && Math.abs(g - rgb[1]) <= tolerance && Math.abs(b - rgb[2]) <= tolerance;

const problems = [];
const check = (ok, message) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${message}`);
  if (!ok) problems.push(message);
};

const profile = mkdtempSync(join(tmpdir(), 'rbcp-view-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: args.chromium,
  headless: true,
  args: CHROMIUM_FLAGS,
  viewport: { width: 1400, height: 900 },
  deviceScaleFactor: 1,
});
try {
  const page = context.pages()[0] ?? (await context.newPage());
  const pageUrl = args.url ?? pathToFileURL(args.page).href;
  const requests = [];
  const consoleErrors = [];
  // Chrome's own network events: playwright's 'request' event misses some failed loads.
  const cdp = await context.newCDPSession(page);
  await cdp.send('Network.enable');
  cdp.on('Network.requestWillBeSent', (event) => requests.push(event.request.url));
  cdp.on('Network.webSocketCreated', (event) => requests.push(event.url));
  page.on('console', (message) => {
    if (message.type() === 'error') consoleErrors.push(message.text());
  });
  page.on('pageerror', (error) => consoleErrors.push(`page error: ${error.message}`));

  await page.goto(pageUrl);
  await page.waitForFunction(() => window.rbcpViewer && window.rbcpViewer.ready, null, { timeout: 120000 });
  const nextFrames = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await nextFrames();

  if (args.live) {
    // The run so far reaches the page: terrain, surfaces, steps walked, the plan ahead, states.
    const enough = () => {
      const live = window.rbcpViewer.live;
      const m = live.messages;
      return live.connected && m.terrain >= 1 && m.surfaces >= 1 && m.walked >= 1 && m.plan >= 1 && m.state >= 40 &&
        window.rbcpViewer.tracks.includes('sim');
    };
    let got = true;
    await page.waitForFunction(enough, null, { timeout: 120000, polling: 250 }).catch(() => (got = false));
    const live = await page.evaluate(() => ({ ...window.rbcpViewer.live }));
    console.log(`     live messages: ${JSON.stringify(live.messages)}; robot at t ${live.lastT}`);
    check(got, 'the live page received the terrain, surfaces, a plan, the walked steps and 40 robot states');
    // The robot's time moves on while the run goes (or the run has ended with a verdict).
    const t0 = live.lastT;
    let moved = true;
    await page.waitForFunction((t) => window.rbcpViewer.live.lastT > t || window.rbcpViewer.live.verdict, t0,
      { timeout: 60000, polling: 250 }).catch(() => (moved = false));
    const after = await page.evaluate(() => ({ t: window.rbcpViewer.live.lastT, verdict: window.rbcpViewer.live.verdict }));
    check(moved, `the live robot moves on (t ${t0} -> ${after.t}${after.verdict ? `, verdict: ${after.verdict.text}` : ''})`);
    await page.evaluate(() => window.rbcpViewer.home());
    await page.waitForTimeout(600);  // the page rebuilds its layers every 200 ms
    await nextFrames();
  }

  const info = await page.evaluate(() => ({
    webgl: window.rbcpViewer.webgl,
    tracks: window.rbcpViewer.tracks,
    status: document.getElementById('status').textContent,
    plots: document.querySelectorAll('#plots svg').length,
    plotTitles: [...document.querySelectorAll('#plots .plot-title')].map((t) => t.textContent),
    legend: document.getElementById('legend').textContent,
    perception: document.getElementById('perception')?.hidden === false ? document.getElementById('perception').textContent : null,
  }));
  check(info.webgl, 'the page draws with WebGL');
  console.log(`     status: ${info.status}; tracks: ${info.tracks.join(', ') || 'none'}; ${info.plots} plots`);
  if (args['expect-status']) {
    check(info.status.includes(args['expect-status']), `the status line says '${args['expect-status']}'`);
  }
  check(['LF', 'RF', 'LH', 'RH'].every((leg) => info.legend.includes(leg)), 'the legend names the four legs');
  for (const text of args['expect-legend']) check(info.legend.includes(text), `the legend says '${text}'`);
  if (info.perception !== null) console.log(`     perception: ${info.perception}`);
  for (const text of args['expect-perception']) {
    check(info.perception !== null && info.perception.includes(text), `the perception panel says '${text}'`);
  }

  const canvas = await page.locator('#view').boundingBox();
  const shot = await page.screenshot({ path: args.screenshot });
  const image = decodePng(shot);
  const area = canvas.width * canvas.height;
  // The leg colours are counted with the robot hidden: on a live page it walks over its footholds
  // and may cover a leg's, depending on the moment.
  await page.evaluate(() => window.rbcpViewer.setLayer('robot', false));
  await nextFrames();
  const unoccluded = decodePng(await page.screenshot());
  const legPixels = Object.fromEntries(Object.entries(LEG_COLORS).map(([leg, rgb]) => [leg, count(unoccluded, canvas, near(rgb))]));
  console.log(`     leg-colour pixels in the 3D view: ${JSON.stringify(legPixels)}`);

  if (info.tracks.length) check(info.plots >= 3, 'the plots are drawn');
  for (const title of args['expect-plot']) {
    check(info.plotTitles.some((t) => t.includes(title)), `a plot of '${title}' (plots: ${info.plotTitles.join('; ')})`);
  }
  if (!args['no-footholds']) {
    for (const [leg, n] of Object.entries(legPixels)) check(n >= 25, `${leg} footholds are drawn in their colour (${n} px)`);
    // Hiding the footholds must take those colours away: they come from the footholds.
    await page.evaluate(() => window.rbcpViewer.setLayer('footholds', false));
    await nextFrames();
    const hidden = decodePng(await page.screenshot());
    await page.evaluate(() => window.rbcpViewer.setLayer('footholds', true));
    const total = (px) => Object.values(px).reduce((a, b) => a + b, 0);
    const left = total(Object.fromEntries(Object.entries(LEG_COLORS).map(([leg, rgb]) => [leg, count(hidden, canvas, near(rgb))])));
    check(left < total(legPixels) * 0.3, `hiding the footholds removes the leg colours (${left} of ${total(legPixels)} px left)`);
  }
  await page.evaluate(() => window.rbcpViewer.setLayer('robot', true));
  await nextFrames();

  /** Pixels of the 3D view that change when the layer is hidden (from the screenshot `shown`). */
  const layerPixels = async (name, shown = image) => {
    await page.evaluate((layer) => window.rbcpViewer.setLayer(layer, false), name);
    await nextFrames();
    const without = decodePng(await page.screenshot());
    await page.evaluate((layer) => window.rbcpViewer.setLayer(layer, true), name);
    return count(shown, canvas, (r, g, b, i) =>
      Math.abs(r - without.pixels[i]) + Math.abs(g - without.pixels[i + 1]) + Math.abs(b - without.pixels[i + 2]) > 40);
  };
  // The terrain covers a good part of the view (a perceived run's elevation map, which lies over
  // it, and true terrain, which shows where it is not, hidden meanwhile).
  const pageLayers = await page.evaluate(() => window.rbcpViewer.layers);
  const aside = ['elevation', 'truth'].filter((name) => pageLayers.includes(name));
  for (const name of aside) await page.evaluate((layer) => window.rbcpViewer.setLayer(layer, false), name);
  if (aside.length) await nextFrames();
  const terrainPixels = await layerPixels('terrain', aside.length ? decodePng(await page.screenshot()) : image);
  for (const name of aside) await page.evaluate((layer) => window.rbcpViewer.setLayer(layer, true), name);
  check(terrainPixels > area * 0.1, `the terrain is drawn (${((100 * terrainPixels) / area).toFixed(0)}% of the 3D view)`);
  if (info.tracks.includes('plan') || info.tracks.includes('sim')) {
    const robotPixels = await layerPixels('robot');
    check(robotPixels > area * 0.002, `the robot is drawn (${robotPixels} px)`);
  }
  if (args['expect-layer'].length) {
    // Halfway through the run, with feet down (at its start the robot may be dropping onto the ground).
    const middle = await page.evaluate(() => {
      window.rbcpViewer.setTime(window.rbcpViewer.duration / 2);
      return window.rbcpViewer.duration / 2;
    });
    await nextFrames();
    const shown = decodePng(await page.screenshot({ path: args.screenshot.replace(/\.png$/, '_middle.png') }));
    for (const name of args['expect-layer']) {
      const n = pageLayers.includes(name) ? await layerPixels(name, shown) : 0;
      check(n >= 30, `the layer '${name}' is drawn at t ${middle.toFixed(2)} (${n} px)`);
    }
    await page.evaluate(() => window.rbcpViewer.setTime(0));
  }
  for (const name of args['no-layer']) check(!pageLayers.includes(name), `the page has no layer '${name}'`);

  if (info.tracks.length && !args.live) {
    // Play for a moment: the timeline moves, and the robot with it.
    // Until the slider has moved (a loaded machine renders few frames a second), 15 s at most.
    await page.click('#play');
    await page
      .waitForFunction(() => Number(document.getElementById('slider').value) > 0, null, { timeout: 15000 })
      .catch(() => {});
    await page.click('#play');
    const t = await page.evaluate(() => Number(document.getElementById('slider').value));
    check(t > 0, `play advances the timeline (to ${t.toFixed(2)})`);
  }

  const allowed = (url) => {
    if (url === pageUrl || url.startsWith('data:') || url.startsWith('blob:')) return true;
    if (!args['allow-host']) return false;
    try {
      return new URL(url).host === args['allow-host'];
    } catch {
      return false;
    }
  };
  const network = requests.filter((url) => !allowed(url));
  const what = args['allow-host'] ? `no network request but to ${args['allow-host']}` : 'no network request';
  check(network.length === 0, network.length
    ? `${what}, but the page requested ${network.slice(0, 5).join(', ')}`
    : `${what} (${requests.length} loads: the page, its inlined modules as blob: URLs${args['allow-host'] ? ', the bridge' : ''})`);
  check(consoleErrors.length === 0, 'no console error' + (consoleErrors.length ? `: ${consoleErrors.slice(0, 5).join(' | ')}` : ''));
} finally {
  await context.close();
  rmSync(profile, { recursive: true, force: true });
}
if (problems.length) {
  console.log(`check_page: ${problems.length} problem(s) on ${args.page ?? args.url}`);
  process.exit(1);
}
console.log(`check_page: ${args.page ?? args.url} ok, screenshot ${args.screenshot}`);
