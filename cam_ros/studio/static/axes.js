// cam_ros studio: adding and removing a machine's axis. The app makes the new values (an axis
// copied from another, or one dropped with every pair naming it) and the core judges them; a
// refused one shows the core's line under the buttons and changes nothing, an accepted one is
// an edit as any other (undo, redo, save). body[data-axis-answers] counts the app's answers.
'use strict';

function axisControl(hook) { return document.querySelector(`#axis-edit [${hook}]`); }

// Show the controls for a machine: the axes to copy, and the shown axis to remove.
function renderAxisEdit() {
  const box = document.getElementById('axis-edit');
  box.hidden = !studio.design.machine;
  if (box.hidden) return;
  const source = axisControl('data-copy-of');
  const chosen = studio.values.axes.includes(source.value) ? source.value : studio.axis;
  source.replaceChildren(...studio.values.axes.map(axis => element('option', {value: axis}, axis)));
  source.value = chosen;
  axisControl('data-action="remove-axis"').textContent = `Remove axis ${studio.axis}`;
}

async function axisEdit(request, shown) {
  const answer = await (await api('api/axes', {values: studio.values, ...request})).json();
  const error = axisControl('data-error-for="axes"');
  error.textContent = answer.error ? answer.error.text : '';
  document.body.dataset.axisAnswers = String(Number(document.body.dataset.axisAnswers || 0) + 1);
  if (answer.error) return;
  edit(values => {
    for (const key of Object.keys(values)) delete values[key];
    Object.assign(values, answer.values);
    if (shown) studio.axis = shown;
  });
}

axisControl('data-action="add-axis"').addEventListener('click', () => {
  const name = axisControl('data-new-axis').value.trim();
  axisEdit({add: name, copy_of: axisControl('data-copy-of').value}, name);
});
axisControl('data-action="remove-axis"').addEventListener('click',
                                                         () => axisEdit({remove: studio.axis}));
