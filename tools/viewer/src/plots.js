// Small SVG plots: time series and a contact timeline (Gantt strip), each with a cursor at the
// current time; a click on a plot seeks there. No plotting library.
const SVG = 'http://www.w3.org/2000/svg';
const MARGIN = { left: 52, right: 12, top: 24, bottom: 28 };

function el(name, attributes = {}, parent = null) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) node.setAttribute(k, v);
  if (parent) parent.appendChild(node);
  return node;
}

/** About `count` round tick values covering [lo, hi]. */
export function niceTicks(lo, hi, count = 5) {
  if (!(hi > lo)) return [lo];
  const raw = (hi - lo) / count;
  const magnitude = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * magnitude).find((s) => s >= raw);
  const ticks = [];
  for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) ticks.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return ticks;
}

function formatTick(v) {
  const a = Math.abs(v);
  if (a === 0) return '0';
  if (a >= 100) return v.toFixed(0);
  if (a >= 10) return v.toFixed(1).replace(/\.0$/, '');
  return String(Number(v.toPrecision(3)));
}

/** Frame of one plot: axes, grid, labels; returns helpers to map data to pixels. */
function frame(container, { title, xLabel, yLabel, xRange, yRange, width, height, yTicks = true }) {
  container.replaceChildren();
  const svg = el('svg', { viewBox: `0 0 ${width} ${height}`, width, height, class: 'plot' }, container);
  const [x0, x1] = xRange;
  const [y0, y1] = yRange;
  const plotW = width - MARGIN.left - MARGIN.right;
  const plotH = height - MARGIN.top - MARGIN.bottom;
  const px = (x) => MARGIN.left + ((x - x0) / (x1 - x0 || 1)) * plotW;
  const py = (y) => MARGIN.top + plotH - ((y - y0) / (y1 - y0 || 1)) * plotH;
  el('rect', { x: MARGIN.left, y: MARGIN.top, width: plotW, height: plotH, class: 'plot-bg' }, svg);
  for (const t of niceTicks(x0, x1, Math.max(2, Math.round(plotW / 70)))) {
    el('line', { x1: px(t), x2: px(t), y1: MARGIN.top, y2: MARGIN.top + plotH, class: 'grid' }, svg);
    el('text', { x: px(t), y: height - MARGIN.bottom + 14, class: 'tick', 'text-anchor': 'middle' }, svg).textContent =
      formatTick(t);
  }
  if (yTicks) {
    for (const t of niceTicks(y0, y1, 4)) {
      el('line', { x1: MARGIN.left, x2: MARGIN.left + plotW, y1: py(t), y2: py(t), class: 'grid' }, svg);
      el('text', { x: MARGIN.left - 6, y: py(t) + 4, class: 'tick', 'text-anchor': 'end' }, svg).textContent =
        formatTick(t);
    }
  }
  el('text', { x: MARGIN.left, y: 15, class: 'plot-title' }, svg).textContent = title;
  el('text', { x: width - MARGIN.right, y: height - 3, class: 'axis-label', 'text-anchor': 'end' }, svg).textContent =
    xLabel;
  if (yLabel) {
    el('text', { x: width - MARGIN.right, y: 15, class: 'axis-label', 'text-anchor': 'end' }, svg).textContent = yLabel;
  }
  const cursor = el('line', { y1: MARGIN.top, y2: MARGIN.top + plotH, class: 'cursor' }, svg);
  return {
    svg,
    px,
    py,
    plotW,
    plotH,
    setCursor(x) {
      const clamped = Math.min(Math.max(x, x0), x1);
      cursor.setAttribute('x1', px(clamped));
      cursor.setAttribute('x2', px(clamped));
    },
    onSeek(callback) {
      svg.addEventListener('click', (event) => {
        const box = svg.getBoundingClientRect();
        const sx = ((event.clientX - box.left) / box.width) * width;
        callback(x0 + ((sx - MARGIN.left) / plotW) * (x1 - x0));
      });
    },
  };
}

/**
 * Time series. series: [{name, color, points: [[x, y], ...], step, dash, markers}] (step: hold
 * each value until the next point; a y that is not finite breaks the line; markers: dots, no
 * line). hlines: [{y, color, label}] reference lines (limits), always in range; yRange: [lo, hi]
 * to fix the range. Returns {setCursor(x), onSeek(callback)}.
 */
export function linePlot(container, { title, xLabel, yLabel, xRange, series, hlines = [], yRange, width = 420, height = 150 }) {
  const ys = series.flatMap((s) => s.points.map((p) => p[1])).filter(Number.isFinite);
  ys.push(...hlines.map((h) => h.y));
  let lo = ys.length ? Math.min(...ys) : 0;
  let hi = ys.length ? Math.max(...ys) : 1;
  const pad = Math.max((hi - lo) * 0.08, 1e-3);
  lo -= pad;
  hi += pad;
  if (yRange) [lo, hi] = yRange;
  const f = frame(container, { title, xLabel, yLabel, xRange, yRange: [lo, hi], width, height });
  for (const h of hlines) {
    el('line', { x1: MARGIN.left, x2: MARGIN.left + f.plotW, y1: f.py(h.y), y2: f.py(h.y), stroke: h.color,
      'stroke-width': 1.2, 'stroke-dasharray': '5 3', class: 'hline' }, f.svg);
    if (h.label) {
      el('text', { x: MARGIN.left + 4, y: f.py(h.y) - 3, class: 'tick', 'text-anchor': 'start', fill: h.color },
        f.svg).textContent = h.label;
    }
  }
  let legendX = MARGIN.left;
  series.forEach((s) => {
    if (s.markers) {
      for (const [x, y] of s.points) {
        if (Number.isFinite(y)) el('circle', { cx: f.px(x), cy: f.py(Math.min(Math.max(y, lo), hi)), r: 2.6, fill: s.color }, f.svg);
      }
    } else {
      const d = [];
      let open = false;
      s.points.forEach(([x, y]) => {
        if (!Number.isFinite(y)) {
          open = false;
          return;
        }
        if (s.step && open) d.push(`H${f.px(x).toFixed(1)}`);
        d.push(`${open ? 'L' : 'M'}${f.px(x).toFixed(1)},${f.py(y).toFixed(1)}`);
        open = true;
      });
      const attributes = { d: d.join(''), class: 'series', stroke: s.color };
      if (s.dash) attributes['stroke-dasharray'] = s.dash;
      el('path', attributes, f.svg);
    }
    if (series.length > 1) {
      // Legend on the x-axis label's line, from the left.
      el('line', { x1: legendX, x2: legendX + 16, y1: height - 7, y2: height - 7, stroke: s.color, 'stroke-width': 2.5 }, f.svg);
      el('text', { x: legendX + 20, y: height - 3, class: 'tick' }, f.svg).textContent = s.name;
      legendX += 26 + 6.5 * s.name.length;
    }
  });
  return f;
}

/**
 * Contact timeline: one row per entry of rows [{name, color, intervals: [[x0, x1], ...]}],
 * filled where the foot is in contact. Returns {setCursor(x), onSeek(callback)}.
 */
export function ganttPlot(container, { title, xLabel, xRange, rows, width = 420, height = 130 }) {
  const f = frame(container, { title, xLabel, xRange, yRange: [0, rows.length], width, height, yTicks: false });
  const rowH = f.plotH / rows.length;
  rows.forEach((row, i) => {
    const y = MARGIN.top + i * rowH;
    el('text', { x: MARGIN.left - 6, y: y + rowH / 2 + 4, class: 'tick', 'text-anchor': 'end' }, f.svg).textContent = row.name;
    for (const [a, b] of row.intervals) {
      el('rect', {
        x: f.px(a),
        y: y + 2,
        width: Math.max(f.px(b) - f.px(a), 0.8),
        height: rowH - 4,
        fill: row.color,
      }, f.svg);
    }
  });
  // Keep the cursor above the bars.
  f.svg.appendChild(f.svg.querySelector('.cursor'));
  return f;
}
