// cam_ros studio, live (`cam_ros studio FILE --node /cam`): the running node's master position
// on the plots, each axis's command and reported position over the timing diagram, its state
// and diagnostics, and the apply, engage and disengage buttons. The app answers in the page's
// units and angles (by the core's mapping); the page only places them. Hooks: data-action
// apply|engage|disengage, data-live-state, data-live-master, data-live-axis, data-live-answer,
// data-live-error; body[data-live-seq] counts the statuses drawn, body[data-live-answers] the
// answers to the buttons.
'use strict';

const LIVE_PERIOD_MS = 250;
// Each axis's command (a dot) and reported position (a ring) over the timing diagram.
const MARKERS = [['command', 'circle', '#0b7'], ['reported', 'circle-open', '#e67e00']];
const live = {node: null, status: null, seq: 0, answers: 0};

function number(value) { return value === null ? '-' : Number(value).toPrecision(6); }

// Draw the live lines and traces over a plot, replacing the last ones.
function overlay(id, lines, traces, config) {
  const plot = document.getElementById(id);
  if (!plot || !plot.data || plot.style.display === 'none') return;
  const data = plot.data.filter(trace => trace.meta !== 'live').concat(traces);
  const shapes = (plot.layout.shapes || []).filter(shape => shape.name !== 'live').concat(lines);
  Plotly.react(plot, data, {...plot.layout, shapes}, config);
}

function masterLine(deg, color = '#0b7') {
  return deg === null ? [] : [{type: 'line', name: 'live', xref: 'x', yref: 'paper', x0: deg,
    x1: deg, y0: 0, y1: 1, editable: false, line: {color, width: 2}}];
}

function drawLive(status) {
  const view = studio.view;
  if (!view) return;
  const shown = status.axes[view.axis || Object.keys(status.axes)[0]];
  const camDeg = shown ? shown.cam_deg : null;
  overlay('svaj', masterLine(camDeg), [], {...CONFIG, edits: {shapePosition: true}});
  overlay('geometry', masterLine(camDeg), [], CONFIG);
  if (!view.timing) return;
  const traces = [];
  Object.keys(view.timing.positions).forEach((name, i) => {
    const axis = status.axes[name];
    if (!axis || status.master_deg === null) return;
    for (const [kind, symbol, color] of MARKERS) {
      if (axis[kind] === null) continue;
      traces.push({x: [status.master_deg], y: [axis[kind]], meta: 'live', mode: 'markers',
        name: `${name} ${kind}`, yaxis: i ? `y${i + 1}` : 'y',
        marker: {symbol, size: 11, color, line: {width: 2, color}},
        hovertemplate: `${name} ${kind}: %{y:.6g} ${axis.unit}<extra></extra>`});
    }
  });
  overlay('timing', masterLine(status.master_deg), traces, CONFIG);
}

function showStatus(status) {
  live.status = status;
  const state = status.state;
  document.querySelector('[data-live-state]').textContent =
    state ? `${state.level}: ${state.message}` : 'no state yet';
  document.querySelector('[data-live-master]').textContent =
    `master ${number(status.master_deg)} deg`;
  document.getElementById('live-axes').replaceChildren(...Object.entries(status.axes).map(
    ([name, axis]) => element('span', {'data-live-axis': name,
      'data-command': axis.command === null ? '' : String(axis.command),
      'data-reported': axis.reported === null ? '' : String(axis.reported)},
      `${name}: command ${number(axis.command)}, reported ${number(axis.reported)} ${axis.unit}`)));
  const failing = status.diagnostics.filter(item => item.level !== 'OK');
  document.getElementById('live-summary').textContent = `diagnostics: ${
    failing.length ? failing.map(item => `${item.name} ${item.level}`).join(', ') : 'all OK'}`;
  document.getElementById('live-diagnostics').replaceChildren(...status.diagnostics.map(
    item => element('li', {class: item.level === 'OK' ? '' : 'fails'},
                    `${item.name}: ${item.level}: ${item.message}`)));
  drawLive(status);
  document.body.dataset.liveSeq = String(++live.seq);
}

async function poll() {
  try {
    const response = await api('api/live');
    if (response.ok) showStatus(await response.json());
  } finally {
    setTimeout(poll, LIVE_PERIOD_MS);
  }
}

// Show the answer to a button: what the node said, or why it refused.
function answered(text, error) {
  document.querySelector('[data-live-answer]').textContent = text;
  document.querySelector('[data-live-error]').textContent = error;
  document.body.dataset.liveAnswers = String(++live.answers);
}

async function post(path, body) {
  const answer = await (await api(path, body)).json();
  if (answer.error) answered('', answer.error.text);
  return answer.error ? null : answer;
}

async function apply() {
  const answer = await post('api/live/apply', {values: studio.values});
  if (!answer) return;
  if (answer.applied) {
    answered(answer.sent.length ? `applied ${answer.sent.join(', ')}` : answer.reason, '');
  } else {
    answered('', `${live.node} refused ${answer.sent.join(', ')}: ${answer.reason}`);
  }
}

async function engage(on) {
  const answer = await post('api/live/engage', {engage: on});
  if (answer) answered(answer.message, answer.success ? '' : `${live.node}: ${answer.message}`);
}

async function startLive() {
  const first = await (await api('api/live')).json();
  if (!first.node) return;
  live.node = first.node;
  document.getElementById('live-actions').hidden = false;
  document.getElementById('live').hidden = false;
  document.getElementById('live-node').textContent = live.node;
  const actions = {apply, engage: () => engage(true), disengage: () => engage(false)};
  for (const [name, act] of Object.entries(actions)) {
    document.querySelector(`[data-action="${name}"]`).addEventListener('click', act);
  }
  showStatus(first);
  setTimeout(poll, LIVE_PERIOD_MS);
}

startLive();
