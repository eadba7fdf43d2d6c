// cam_ros studio: the page. It holds the design's values as the texts a user types, sends them
// to the app on every edit and draws what the app answers (the core's numbers); it computes
// nothing of the design itself. Hooks kept for tests and scripts: data-key, data-error-for,
// data-verdict, data-pair, data-action (see docs/studio.md).
'use strict';

const studio = {
  design: null,      // {label, name, machine, read_only, values, laws, parameters}
  values: {},        // parameter name -> text, or list of texts
  undo: [], redo: [],
  axis: null,        // the machine axis shown
  view: null,        // the last view the app drew
  seq: 0,            // edits sent; the page shows only the newest answer
  angle: 0,
};

const SEGMENT_ORDER = ['laws', 'start_deg', 'end_deg', 'start_position', 'end_position'];
const DERIVATIVES = ['velocity', 'acceleration', 'jerk'];

async function api(path, body) {
  const response = await fetch(path, body === undefined ? {} : {
    method: 'POST', headers: {'Content-Type': 'application/json'}, body: JSON.stringify(body)});
  return response;
}

function clone(values) { return JSON.parse(JSON.stringify(values)); }
function prefix() { return studio.design.machine ? `${studio.axis}.` : ''; }
function element(tag, attributes = {}, text = '') {
  const node = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) node.setAttribute(name, value);
  if (text) node.textContent = text;
  return node;
}

// ---------------------------------------------------------------------------- editing

function valueAt(key) {
  const match = key.match(/^(.*)\[(\d+)\]$/);
  return match ? studio.values[match[1]][Number(match[2])] : studio.values[key];
}

function shape(values) {
  return JSON.stringify(Object.entries(values).map(([key, value]) =>
    [key, Array.isArray(value) ? value.length : -1]));
}

// Show the values in the fields: rebuilt when keys or lengths changed, else only refilled.
function refresh(before) {
  if (before !== shape(studio.values)) { render(); return; }
  for (const box of document.querySelectorAll('input[data-key]')) {
    const value = valueAt(box.dataset.key);
    if (box.value !== value) box.value = value;
  }
  document.querySelector('[data-action="undo"]').disabled = !studio.undo.length;
  document.querySelector('[data-action="redo"]').disabled = !studio.redo.length;
}

function edit(change) {
  const before = shape(studio.values);
  studio.undo.push(clone(studio.values));
  studio.redo = [];
  change(studio.values);
  refresh(before);
  update();
}

function setValue(key, text) {
  if (valueAt(key) === text) return;
  edit(values => {
    const match = key.match(/^(.*)\[(\d+)\]$/);
    if (match) values[match[1]][Number(match[2])] = text; else values[key] = text;
  });
}

function input(key, className = '') {
  const cell = element('span', {class: 'cell'});
  const box = element('input', {'data-key': key, class: className, title: help(key)});
  box.value = valueAt(key);
  if (className === 'law') box.setAttribute('list', 'law-names');
  box.addEventListener('change', () => setValue(key, box.value));
  box.addEventListener('keydown', event => { if (event.key === 'Enter') box.blur(); });
  cell.append(box, element('div', {class: 'error', 'data-error-for': key}));
  return cell;
}

function help(key) {
  const name = key.replace(/\[\d+\]$/, '');
  const axes = studio.design.machine ? studio.values.axes : [];
  const bare = axes.reduce((n, axis) => n.startsWith(`${axis}.`) ? n.slice(axis.length + 1) : n,
                           name);
  return studio.design.parameters[bare] || name;
}

function field(key, label = key) {
  const row = element('div', {class: 'field'});
  row.append(element('label', {title: help(key)}, label));
  const value = studio.values[key];
  const holder = element('span');
  if (Array.isArray(value)) value.forEach((_, i) => holder.append(input(`${key}[${i}]`)));
  else holder.append(input(key));
  row.append(holder);
  return row;
}

function segmentKeys() {
  const head = `${prefix()}motion.`;
  const count = (studio.values[`${head}laws`] || []).length;
  const keys = Object.keys(studio.values).filter(
    key => key.startsWith(head) && Array.isArray(studio.values[key])
      && studio.values[key].length === count && !key.slice(head.length).startsWith('via_'));
  const rank = key => { const i = SEGMENT_ORDER.indexOf(key.slice(head.length));
                        return i < 0 ? SEGMENT_ORDER.length : i; };
  return keys.sort((a, b) => rank(a) - rank(b));
}

// A double as a parameters file needs it: with a decimal point or an exponent.
function floatText(number) {
  const text = String(number);
  return /[.eE]|n/.test(text) ? text : `${text}.0`;
}

// Split a segment into two of its law, meeting at its middle angle at the position the motion
// has there (asked of the app); their inner velocities and higher derivatives are left free.
async function split(index) {
  const head = `${prefix()}motion.`;
  const start = Number(studio.values[`${head}start_deg`][index]);
  const end = Number(studio.values[`${head}end_deg`][index]);
  const middle = floatText((start + end) / 2);
  const answer = await (await api('api/position', {values: studio.values, axis: studio.axis,
                                                   deg: (start + end) / 2})).json();
  if (answer.error) { showErrors(answer.error); return; }
  const position = floatText(Number(answer.position.toPrecision(12)));
  const inner = {end_deg: [0, middle], start_deg: [1, middle], end_position: [0, position],
                 start_position: [1, position]};
  for (const kind of DERIVATIVES) { inner[`end_${kind}`] = [0, '.nan']; inner[`start_${kind}`] = [1, '.nan']; }
  edit(values => {
    for (const key of segmentKeys()) {
      const list = values[key], name = key.slice(head.length);
      list.splice(index + 1, 0, list[index]);
      if (name in inner) list[index + inner[name][0]] = inner[name][1];
    }
  });
}

function removeSegment(index) {
  const head = `${prefix()}motion.`;
  edit(values => {
    const keys = segmentKeys();
    const last = index === values[`${head}laws`].length - 1;
    const keep = last ? index - 1 : index + 1;  // the neighbour takes the removed span
    for (const key of keys) {
      const name = key.slice(head.length), list = values[key];
      if (last && (name.startsWith('end_'))) list[keep] = list[index];
      if (!last && (name.startsWith('start_'))) list[keep] = list[index];
    }
    for (const key of keys) values[key].splice(index, 1);
  });
}

function renderMotion() {
  const table = document.getElementById('motion');
  table.replaceChildren();
  const head = `${prefix()}motion.`;
  const keys = segmentKeys();
  const header = element('tr');
  header.append(element('th', {}, '#'));
  for (const key of keys) header.append(element('th', {title: help(key)}, key.slice(head.length)));
  table.append(header);
  const count = (studio.values[`${head}laws`] || []).length;
  for (let i = 0; i < count; i++) {
    const row = element('tr');
    row.append(element('td', {}, String(i)));
    for (const key of keys) {
      const cell = element('td');
      cell.append(input(`${key}[${i}]`, key.endsWith('laws') ? 'law' : ''));
      row.append(cell);
    }
    const tools = element('td');
    const splitter = element('button', {title: 'split at the middle angle'}, 'split');
    splitter.addEventListener('click', () => split(i));
    const remover = element('button', {title: 'remove (its neighbour takes its span)'}, '×');
    remover.addEventListener('click', () => removeSegment(i));
    tools.append(splitter);
    if (count > 1) tools.append(remover);
    row.append(tools);
    table.append(row);
  }
  const add = element('button', {title: 'add a segment: split the last one'}, 'add segment');
  add.addEventListener('click', () => split(count - 1));
  const extra = document.getElementById('motion-extra');
  extra.replaceChildren(add);
  for (const key of Object.keys(studio.values).filter(
    k => k.startsWith(head) && !keys.includes(k))) extra.append(field(key, key.slice(head.length)));
}

function renderFields() {
  const own = document.getElementById('fields');
  own.replaceChildren();
  const start = prefix();
  const wide = studio.design.machine ? studio.values.axes.map(axis => `${axis}.`) : [];
  own.append(element('h2', {}, studio.design.machine ? `Axis ${studio.axis}` : 'Design'));
  for (const key of Object.keys(studio.values)) {
    if (key.startsWith(start) && !key.startsWith(`${start}motion.`)
        && (start || !wide.some(p => key.startsWith(p)))) {
      own.append(field(key, key.slice(start.length)));
    }
  }
  const machine = document.getElementById('machine-fields');
  machine.replaceChildren();
  const pairKeys = Object.keys(studio.values).filter(k => k.startsWith('interference.'));
  document.getElementById('pairs-title').style.display = pairKeys.length ? '' : 'none';
  const table = document.getElementById('pairs-table');
  table.replaceChildren();
  if (!studio.design.machine) return;
  machine.append(element('h2', {}, 'Machine'));
  for (const key of Object.keys(studio.values)) {
    if (!wide.some(p => key.startsWith(p)) && !key.startsWith('interference.')) {
      machine.append(field(key));
    }
  }
  if (!pairKeys.length) return;
  const header = element('tr');
  for (const key of pairKeys) header.append(element('th', {title: help(key)},
                                                    key.slice('interference.'.length)));
  table.append(header);
  const count = studio.values['interference.axis_a'].length;
  for (let i = 0; i < count; i++) {
    const row = element('tr');
    for (const key of pairKeys) { const td = element('td'); td.append(input(`${key}[${i}]`)); row.append(td); }
    table.append(row);
  }
}

function renderTabs() {
  const tabs = document.getElementById('axis-tabs');
  tabs.replaceChildren();
  if (!studio.design.machine) return;
  for (const axis of studio.values.axes) {
    const tab = element('button', {class: axis === studio.axis ? 'current' : '',
                                   'data-axis': axis}, axis);
    tab.addEventListener('click', () => { studio.axis = axis; render(); update(); });
    tabs.append(tab);
  }
}

function render() {
  if (studio.design.machine && !studio.values.axes.includes(studio.axis)) {
    studio.axis = studio.values.axes[0];
  }
  renderTabs();
  renderMotion();
  renderFields();
  renderAxisEdit();
  document.querySelector('[data-action="undo"]').disabled = !studio.undo.length;
  document.querySelector('[data-action="redo"]').disabled = !studio.redo.length;
}

// ---------------------------------------------------------------------------- the app's answer

function clearErrors() {
  for (const node of document.querySelectorAll('[data-error-for]')) node.textContent = '';
  for (const node of document.querySelectorAll('input.bad')) node.classList.remove('bad');
}

function showErrors(error) {
  clearErrors();
  const key = error.key;
  const base = key.replace(/\[\d+\]$/, '');
  const target = [key, `${base}[0]`, base].map(
    k => document.querySelector(`[data-error-for="${CSS.escape(k)}"]`)).find(Boolean);
  (target || document.getElementById('general-error')).textContent = error.text;
  const box = document.querySelector(`[data-key="${CSS.escape(key)}"]`);
  if (box) box.classList.add('bad');
  document.getElementById('verdict').classList.add('stale');
}

async function update() {
  const seq = ++studio.seq;
  document.body.dataset.state = 'busy';
  const response = await api('api/view', {values: studio.values, axis: studio.axis});
  const answer = await response.json();
  if (seq !== studio.seq) return;
  if (answer.error) {
    showErrors(answer.error);
    document.body.dataset.state = 'error';
  } else {
    clearErrors();
    studio.view = answer;
    draw(answer);
    document.body.dataset.state = 'ready';
  }
  document.body.dataset.seq = String(seq);
}

function draw(view) {
  const verdict = document.getElementById('verdict');
  verdict.textContent = view.verdict;
  verdict.className = view.ok ? 'ok' : 'fails';
  const checks = document.getElementById('checks');
  checks.replaceChildren();
  for (const check of view.checks) {
    for (const warning of check.warnings) {
      checks.append(element('li', {class: check.ok ? '' : 'fails'},
                            (check.axis ? `axis ${check.axis}: ` : '') + warning));
    }
  }
  const pairs = document.getElementById('pair-figures');
  pairs.replaceChildren();
  for (const pair of view.pairs) {
    pairs.append(element('li', {'data-pair': pair.pair, class: pair.ok ? '' : 'fails'}, pair.line));
  }
  const curves = view.curves, part = keys => keys.map(key => [key, curves[key]]);
  // a cam_speed edit moves V, A, J only: the geometry plot is drawn again when its data change
  changed('svaj', part(Object.keys(curves).filter(key => !GEOMETRY.includes(key))))
    && drawCurves(curves);
  changed('geometry', part(['angle_deg', 'joints_deg', ...GEOMETRY])) && drawGeometry(curves);
  changed('drawing', [view.drawing, studio.angle]) && drawDrawing(view.drawing);
  changed('timing', [view.timing, view.pairs]) && drawTiming(view);
}

const drawn = {};
// The curves' entries drawn on the pressure angle and radius of curvature plot only.
const GEOMETRY = ['pressure_angle_deg', 'pressure_limit_deg', 'pressure_return_limit_deg',
                  'radius', 'radius_unit', 'radius_limit'];

// Say whether a plot's data differ from what it shows (then remember them).
function changed(plot, data) {
  const text = JSON.stringify(data);
  if (drawn[plot] === text) return false;
  drawn[plot] = text;
  return true;
}

const CONFIG = {responsive: true, displaylogo: false};

function jointShapes(curves, yref, editable) {
  return curves.joints_deg.filter(deg => deg > 0).map(deg => ({
    type: 'line', xref: 'x', yref, x0: deg, x1: deg, y0: 0, y1: 1,
    line: {color: '#999', width: editable ? 2 : 1, dash: 'dot'}, editable}));
}

function drawCurves(curves) {
  const unit = curves.unit;
  const rows = [['position', `S (${unit})`, '#1f77b4'], ['velocity', `V (${unit}/s)`, '#2ca02c'],
                ['acceleration', `A (${unit}/s²)`, '#d62728'], ['jerk', `J (${unit}/s³)`, '#9467bd']];
  const traces = rows.map(([name, label, color], i) => ({
    x: curves.angle_deg, y: curves[name], name: label, line: {color, width: 1.5},
    yaxis: i ? `y${i + 1}` : 'y', hovertemplate: `%{x:.2f} deg: %{y:.6g} ${label}<extra></extra>`}));
  const layout = {margin: {l: 70, r: 10, t: 28, b: 36}, showlegend: false,
    title: {text: `S-V-A-J at ${curves.cam_speed.toPrecision(6)} rad/s (drag a joint on S)`,
            font: {size: 13}},
    xaxis: {range: [0, 360], dtick: 30, title: {text: 'cam angle (deg)'}, anchor: 'y4'},
    shapes: jointShapes(curves, 'y domain', true),
    annotations: curves.laws.map((law, i) => ({x: curves.joints_deg[i] % 360, y: 1, yref: 'y domain',
      text: law, showarrow: false, xanchor: 'left', yanchor: 'top', font: {size: 9, color: '#555'}}))};
  rows.forEach(([, label], i) => {
    layout[i ? `yaxis${i + 1}` : 'yaxis'] = {title: {text: label, font: {size: 11}},
      domain: [(3 - i) * 0.25 + 0.02, (4 - i) * 0.25 - 0.02]};
  });
  Plotly.react('svaj', traces, layout, {...CONFIG, edits: {shapePosition: true}});
}

function drawGeometry(curves) {
  const geometry = document.getElementById('geometry');
  if (curves.pressure_angle_deg === undefined) { Plotly.purge(geometry); geometry.style.display = 'none'; return; }
  geometry.style.display = '';
  const limit = curves.pressure_limit_deg, back = curves.pressure_return_limit_deg;
  const line = (y, axis, color, dash) => ({type: 'line', xref: 'x', yref: axis, x0: 0, x1: 360,
                                           y0: y, y1: y, line: {color, width: 1, dash}});
  const shapes = [line(limit, 'y', '#d62728', 'dash'), line(-limit, 'y', '#d62728', 'dash')];
  if (back !== limit) shapes.push(line(back, 'y', '#ff7f0e', 'dot'), line(-back, 'y', '#ff7f0e', 'dot'));
  if (curves.radius_limit > 0) shapes.push(line(curves.radius_limit, 'y2', '#d62728', 'dash'));
  Plotly.react('geometry', [
    {x: curves.angle_deg, y: curves.pressure_angle_deg, name: 'pressure angle', line: {color: '#1f77b4'},
     hovertemplate: '%{x:.2f} deg: %{y:.4f} deg<extra></extra>'},
    {x: curves.angle_deg, y: curves.radius, name: 'radius of curvature', yaxis: 'y2',
     line: {color: '#2ca02c'}, hovertemplate: `%{x:.2f} deg: %{y:.6g} ${curves.radius_unit}<extra></extra>`},
  ], {margin: {l: 70, r: 10, t: 28, b: 36}, showlegend: false,
      title: {text: `Pressure angle (limit ±${limit} deg) and radius of curvature`, font: {size: 13}},
      xaxis: {range: [0, 360], dtick: 30, anchor: 'y2'},
      yaxis: {title: {text: 'pressure angle (deg)', font: {size: 11}}, domain: [0.55, 1]},
      yaxis2: {title: {text: `radius (${curves.radius_unit})`, font: {size: 11}}, domain: [0, 0.45]},
      shapes: shapes.concat(jointShapes(curves, 'paper', false))}, CONFIG);
}

function turned(points, angle) {
  const c = Math.cos(angle), s = Math.sin(angle);
  return [points[0].map((x, i) => c * x - s * points[1][i]),
          points[0].map((x, i) => s * x + c * points[1][i])];
}

function drawDrawing(drawing) {
  const box = document.getElementById('drawing-box');
  if (!drawing) { box.classList.add('none'); Plotly.purge('drawing'); return; }
  box.classList.remove('none');
  const sigma = drawing.clockwise ? -1 : 1;
  const turn = sigma * studio.angle * Math.PI / 180;
  const closed = p => [p[0].concat([p[0][0]]), p[1].concat([p[1][0]])];
  const surface = closed(turned(drawing.surface, turn));
  const pitch = closed(turned(drawing.pitch, turn));
  const circle = (r, cx = 0, cy = 0) => {
    const t = Array.from({length: 181}, (_, i) => i * 2 * Math.PI / 180);
    return [t.map(a => cx + r * Math.cos(a)), t.map(a => cy + r * Math.sin(a))];
  };
  const base = circle(drawing.base_radius_mm);
  const traces = [
    {x: surface[0], y: surface[1], name: 'cam surface', fill: 'toself', line: {color: '#1f77b4'}},
    {x: pitch[0], y: pitch[1], name: 'pitch curve', line: {color: '#ff7f0e', dash: 'dash', width: 1}},
    {x: base[0], y: base[1], name: 'base circle', line: {color: '#888', dash: 'dot', width: 1}}];
  for (const [name, points] of Object.entries(drawing.others)) {
    const other = closed(turned(points, turn));
    traces.push({x: other[0], y: other[1], name, line: {color: '#9467bd'}});
  }
  if (drawing.roller_radius_mm > 0) {
    // the roller's centre is the pitch point the follower meets at this cam angle: the pitch
    // curve's sample of the drawn angle, turned with the cam
    const n = drawing.pitch[0].length;
    const i = Math.round(studio.angle / 360 * n) % n;
    const roller = circle(drawing.roller_radius_mm, pitch[0][i], pitch[1][i]);
    traces.push({x: roller[0], y: roller[1], name: 'roller', line: {color: '#d62728'}});
  }
  Plotly.react('drawing', traces, {margin: {l: 50, r: 10, t: 28, b: 36},
    title: {text: `Cam at ${studio.angle} deg (mm)`, font: {size: 13}},
    xaxis: {scaleanchor: 'y', title: {text: 'x (mm)'}}, yaxis: {title: {text: 'y (mm)'}},
    legend: {font: {size: 10}}}, CONFIG);
}

const PAIR_COLORS = ['rgba(214,39,40,0.25)', 'rgba(255,127,14,0.25)'];

function drawTiming(view) {
  const node = document.getElementById('timing');
  node.style.display = view.timing ? '' : 'none';  // shown before drawing: plotly measures it
  if (!view.timing) { Plotly.purge(node); return; }
  const timing = view.timing, names = Object.keys(timing.positions), n = names.length;
  const traces = names.map((name, i) => ({
    x: timing.angle_deg, y: timing.positions[name], name: `${name} (${timing.units[name]})`,
    yaxis: i ? `y${i + 1}` : 'y',
    hovertemplate: `${name}: %{x:.2f} deg, %{y:.6g} ${timing.units[name]}<extra></extra>`}));
  const layout = {margin: {l: 70, r: 10, t: 28, b: 36}, showlegend: false, height: 90 + 110 * n,
    title: {text: 'Timing diagram over the machine cycle', font: {size: 13}},
    xaxis: {range: [0, 360], dtick: 30, title: {text: 'machine angle (deg)'}, anchor: `y${n > 1 ? n : ''}`},
    shapes: []};
  names.forEach((name, i) => {
    layout[i ? `yaxis${i + 1}` : 'yaxis'] = {title: {text: name, font: {size: 11}},
      domain: [(n - 1 - i) / n + 0.02, (n - i) / n - 0.02]};
  });
  for (const pair of view.pairs) {
    for (const [from, to, color] of timing.spans[pair.pair] || []) {
      layout.shapes.push({type: 'rect', xref: 'x', yref: 'paper', x0: from, x1: to, y0: 0, y1: 1,
        fillcolor: color === 'tab:red' ? PAIR_COLORS[0] : PAIR_COLORS[1], line: {width: 0}});
    }
    layout.shapes.push({type: 'line', xref: 'x', yref: 'paper', x0: pair.at_deg, x1: pair.at_deg,
      y0: 0, y1: 1, line: {color: pair.ok ? '#555' : '#d62728', dash: 'dot', width: 1}});
  }
  Plotly.react(node, traces, layout, CONFIG);
}

// ---------------------------------------------------------------------------- dragging joints

function onRelayout(event) {
  const moved = Object.keys(event).find(key => /^shapes\[\d+\]\.x0$/.test(key));
  if (!moved || !studio.view) return;
  const index = Number(moved.match(/\d+/)[0]);
  const joints = studio.view.curves.joints_deg.filter(deg => deg > 0);
  const segment = studio.view.curves.joints_deg.indexOf(joints[index]);
  const text = floatText(Math.round(event[moved] * 100) / 100);
  const head = `${prefix()}motion.`;
  edit(values => {
    values[`${head}end_deg`][segment - 1] = text;
    values[`${head}start_deg`][segment] = text;
  });
}

// ---------------------------------------------------------------------------- actions

async function save() {
  const response = await api('api/save', {values: studio.values});
  const answer = await response.json();
  const saved = document.getElementById('saved');
  if (answer.error) { showErrors(answer.error); saved.textContent = ''; return; }
  saved.textContent = `saved ${answer.saved}`;
  document.getElementById('report').textContent = answer.report;
  document.body.dataset.saved = String(studio.seq);
}

async function showReport(json) {
  const answer = await (await api('api/report', {values: studio.values, json})).json();
  if (answer.error) { showErrors(answer.error); return; }
  document.getElementById('report').textContent = answer.text;
}

function offer(blob, name) {
  const link = element('a', {href: URL.createObjectURL(blob), download: name});
  document.body.append(link);
  link.click();
  link.remove();
}

async function download() {
  const kind = document.getElementById('export-kind').value;
  const text = id => document.getElementById(id).value.trim() || null;
  const message = document.getElementById('export-message');
  const stem = studio.design.name.replace(/\.[^.]*$/, '');
  if (kind.startsWith('report')) {
    const json = kind === 'report-json';
    const answer = await (await api('api/report', {values: studio.values, json})).json();
    if (answer.error) { message.textContent = answer.error.text; return; }
    offer(new Blob([answer.text + '\n']), `${stem}-report.${json ? 'json' : 'txt'}`);
    return;
  }
  const machineWide = ['timing', 'timing-plot', 'switches'].includes(kind);
  const options = {file_format: text('export-format'), tolerance: text('export-tolerance'),
                   cutter_radius: text('export-cutter')};
  const response = await api('api/export', {values: studio.values, kind, options,
    axis: studio.design.machine && !machineWide ? studio.axis : null});
  if (!response.ok) { message.textContent = (await response.json()).error.text; return; }
  const name = response.headers.get('Content-Disposition').match(/filename="(.*)"/)[1];
  message.textContent = response.headers.get('X-Cam-Ros-Message') || '';
  offer(await response.blob(), name);
}

function step(from, to) {
  if (!from.length) return;
  const before = shape(studio.values);
  to.push(clone(studio.values));
  studio.values = from.pop();
  refresh(before);
  update();
}

async function start() {
  studio.design = await (await api('api/design')).json();
  studio.values = studio.design.values;
  const file = document.getElementById('file');
  file.textContent = studio.design.name + (studio.design.read_only ? ' (read-only)' : '');
  file.title = studio.design.label;
  document.querySelector('[data-action="save"]').disabled = studio.design.read_only;
  for (const [list, names] of [['law-names', studio.design.laws],
                               ['parameter-names', Object.keys(studio.design.parameters)]]) {
    document.getElementById(list).replaceChildren(...names.map(name => element('option', {value: name})));
  }
  const actions = {save, undo: () => step(studio.undo, studio.redo),
                   redo: () => step(studio.redo, studio.undo)};
  for (const [name, act] of Object.entries(actions)) {
    document.querySelector(`[data-action="${name}"]`).addEventListener('click', act);
  }
  document.addEventListener('keydown', event => {
    if (!(event.ctrlKey || event.metaKey) || event.target.tagName === 'INPUT') return;
    if (event.key === 'z') actions.undo(); else if (event.key === 'y') actions.redo();
  });
  document.getElementById('report-text').addEventListener('click', () => showReport(false));
  document.getElementById('report-json').addEventListener('click', () => showReport(true));
  document.getElementById('download').addEventListener('click', download);
  document.getElementById('add-button').addEventListener('click', () => {
    const name = document.getElementById('add-name').value.trim();
    const text = document.getElementById('add-value').value.trim();
    if (!name) return;
    const list = text.match(/^\[(.*)\]$/);
    edit(values => { values[name] = list ? list[1].split(',').map(s => s.trim()) : text; });
  });
  const slider = document.getElementById('angle');
  slider.addEventListener('input', () => {
    studio.angle = Number(slider.value);
    document.getElementById('angle-text').textContent = `${studio.angle} deg`;
    if (studio.view) drawDrawing(studio.view.drawing);
  });
  render();
  await update();
  document.getElementById('svaj').on('plotly_relayout', onRelayout);
}

start();
