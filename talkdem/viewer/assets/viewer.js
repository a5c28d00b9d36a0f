(function(){
'use strict';
var D = window.TALKDEM_VIEWER_INDEX;
var $ = function(id){return document.getElementById(id);};
if (!D) { $('summary').textContent = 'data/index.js is missing: open the index.html that talkdem view wrote.'; return; }
var F = {}; D.fields.forEach(function(name, i){F[name] = i;});
var rows = D.rows, PAGE = 100, TYPES = {}, STORE = 'talkdem-viewer-labels/' + D.id;
D.types.forEach(function(t){TYPES[t[0]] = t;});
var chunks = {}, waiting = {}, view = [], page = 0, selected = 0, opened = -1, labels = {};
try { labels = JSON.parse(localStorage.getItem(STORE) || '{}') || {}; } catch (e) { labels = {}; }

function el(tag, attrs, text){
  var e = document.createElement(tag);
  if (attrs) Object.keys(attrs).forEach(function(k){ if (k === 'cls') e.className = attrs[k]; else e.setAttribute(k, attrs[k]); });
  if (text !== undefined && text !== null) e.textContent = String(text);
  return e;
}
function run(r){ return D.runs[r[F.run]]; }
/* Labels are kept by the run's key, not its display label (which depends on the runs shown together). */
function key(r){ return run(r).key + '\n' + r[F.episode_id]; }
function condition(r){ return r[F.pattern] === 'clean' ? 'clean' : r[F.pattern] + ':' + r[F.level]; }
function conditionName(r){
  if (r[F.pattern] === 'clean') return 'Clean';
  var p = D.patterns[r[F.pattern]]; return (p ? p[0] : r[F.pattern]) + ' L' + r[F.level];
}
function taskId(r){ return r[F.episode_id].split(':')[0]; }
function task(r){ return D.tasks[taskId(r)] || {type: '', clean: '', reference: []}; }
function labellable(r){ return r[F.pattern] !== 'clean' && !r[F.success]; }

/* ---- filters ---- */
var FILTERS = [
  ['f-run', 'All runs', function(){ return D.runs.map(function(x, i){ return [String(i), x.label]; }); },
   function(r, v){ return String(r[F.run]) === v; }],
  ['f-pattern', 'All patterns', function(){ return [['clean', 'Clean']].concat(Object.keys(D.patterns).map(function(p){ return [p, D.patterns[p][0]]; })); },
   function(r, v){ return r[F.pattern] === v; }],
  ['f-level', 'All levels', function(){ return [['0', 'clean (0)'], ['1', 'level 1'], ['2', 'level 2'], ['3', 'level 3']]; },
   function(r, v){ return String(r[F.level]) === v; }],
  ['f-type', 'All task types', function(){ var seen = {}; Object.keys(D.tasks).forEach(function(t){ seen[D.tasks[t].type] = 1; });
     return Object.keys(seen).sort().map(function(t){ return [t, t.replace(/_/g, ' ')]; }); },
   function(r, v){ return task(r).type === v; }],
  ['f-outcome', 'Any outcome', function(){ return [['1', 'success'], ['0', 'failure'], ['retention', 'failed, solved clean']]; },
   function(r, v){ return v === 'retention' ? (!r[F.success] && r[F.clean_solved] === 1 && r[F.pattern] !== 'clean') : String(r[F.success]) === v; }],
  ['f-hazard', 'Any hazard', function(){ return [['any', 'any hazard'], ['none', 'no hazard']].concat(D.hazard_categories.map(function(h){ return [h, h.replace(/_/g, ' ')]; })); },
   function(r, v){ var h = r[F.hazards]; return v === 'any' ? h !== '' : v === 'none' ? h === '' : (' ' + h + ' ').indexOf(' ' + v + ' ') >= 0; }],
  ['f-error', 'Any automatic error type', function(){ return D.types.map(function(t){ return [t[0], t[1]]; }); },
   function(r, v){ return r[F.error] === v; }],
  ['f-label', 'Labelling: all', function(){ var o = [['failures', 'failures under a pattern'], ['labelled', 'labelled'], ['unlabelled', 'not labelled yet']];
     return D.sample ? [['sample', 'error sample']].concat(o) : o; },
   function(r, v){ if (v === 'sample') return r[F.sampled] === 1; if (v === 'failures') return labellable(r);
     var has = labels.hasOwnProperty(key(r)); return v === 'labelled' ? has : labellable(r) && !has; }]
];
FILTERS.forEach(function(f){
  var s = $(f[0]); s.appendChild(el('option', {value: ''}, f[1]));
  f[2]().forEach(function(o){ s.appendChild(el('option', {value: o[0]}, o[1])); });
  s.addEventListener('change', function(){ refresh(true); });
});
var haystack = null;
function searchText(i){
  if (!haystack) haystack = new Array(rows.length);
  if (haystack[i] === undefined) { var r = rows[i];
    haystack[i] = (r[F.instruction] + ' ' + r[F.episode_id] + ' ' + run(r).label + ' ' + task(r).type).toLowerCase(); }
  return haystack[i];
}
function filtered(){
  var active = FILTERS.map(function(f){ return [$(f[0]).value, f[3]]; }).filter(function(a){ return a[0] !== ''; });
  var words = $('search').value.toLowerCase().split(/\s+/).filter(Boolean), out = [];
  for (var i = 0; i < rows.length; i++) {
    var r = rows[i], keep = true;
    for (var a = 0; a < active.length && keep; a++) keep = active[a][1](r, active[a][0]);
    for (var w = 0; w < words.length && keep; w++) keep = searchText(i).indexOf(words[w]) >= 0;
    if (keep) out.push(i);
  }
  return out;
}

/* ---- the table ---- */
function tags(td, r){
  r[F.hazards].split(' ').filter(Boolean).forEach(function(h){ td.appendChild(el('span', {cls: 'tag hz', title: 'hazard'}, h.replace(/_/g, ' '))); });
}
function renderTable(){
  var body = $('episodes').tBodies[0], frag = document.createDocumentFragment();
  var start = page * PAGE, end = Math.min(view.length, start + PAGE);
  for (var n = start; n < end; n++) {
    var i = view[n], r = rows[i], tr = el('tr', {'data-row': String(i)});
    if (n === selected) tr.className = 'sel';
    tr.appendChild(el('td', null, run(r).label));
    tr.appendChild(el('td', {title: r[F.episode_id]}, taskId(r).replace(/^trial_/, '')));
    tr.appendChild(el('td', null, conditionName(r)));
    tr.appendChild(el('td', null, task(r).type.replace(/_/g, ' ')));
    var out = el('td', {cls: r[F.success] ? 'ok' : 'fail'}, r[F.success] ? 'success' : 'failure');
    tr.appendChild(out);
    var notes = el('td'); tags(notes, r);
    if (r[F.error]) notes.appendChild(el('span', {cls: 'tag err', title: 'automatic error type'}, TYPES[r[F.error]][2]));
    if (r[F.sampled]) notes.appendChild(el('span', {cls: 'tag smp'}, 'sample'));
    if (labels.hasOwnProperty(key(r))) notes.appendChild(el('span', {cls: 'tag lab', title: 'your label'}, 'labelled: ' + TYPES[labels[key(r)]][2]));
    tr.appendChild(notes);
    tr.appendChild(el('td', {cls: 'num'}, r[F.plan_length]));
    tr.appendChild(el('td', {cls: 'instr', title: r[F.instruction]}, r[F.instruction]));
    frag.appendChild(tr);
  }
  body.textContent = ''; body.appendChild(frag);
  var pages = Math.max(1, Math.ceil(view.length / PAGE));
  $('page').textContent = 'page ' + (page + 1) + ' of ' + pages;
  $('prev').disabled = page === 0; $('next').disabled = page >= pages - 1;
  $('count').textContent = view.length.toLocaleString('en') + ' of ' + rows.length.toLocaleString('en') + ' episodes';
}
function refresh(reset){
  var t0 = performance.now();
  view = filtered();
  if (reset) { selected = 0; page = 0; }
  selected = Math.min(selected, Math.max(0, view.length - 1));
  renderTable();
  document.body.dataset.filterMs = (performance.now() - t0).toFixed(1);
  updateProgress();
}
$('search').addEventListener('input', function(){ refresh(true); });
$('prev').addEventListener('click', function(){ if (page > 0) { page--; selected = page * PAGE; renderTable(); } });
$('next').addEventListener('click', function(){ if ((page + 1) * PAGE < view.length) { page++; selected = page * PAGE; renderTable(); } });
$('episodes').tBodies[0].addEventListener('click', function(ev){
  var tr = ev.target.closest('tr'); if (!tr) return;
  selected = view.indexOf(Number(tr.dataset.row)); renderTable(); openRow(Number(tr.dataset.row));
});
function move(delta){
  if (!view.length) return;
  selected = Math.max(0, Math.min(view.length - 1, selected + delta));
  var want = Math.floor(selected / PAGE); if (want !== page) page = want;
  renderTable();
  var tr = $('episodes').querySelector('tr.sel'); if (tr && tr.scrollIntoView) tr.scrollIntoView({block: 'nearest'});
  if (opened >= 0) openRow(view[selected]);
}

/* ---- details, loaded a chunk at a time ---- */
window.TALKDEM_VIEWER_CHUNK = function(n, data){
  chunks[n] = data; var w = waiting[n] || []; delete waiting[n]; w.forEach(function(f){ f(); });
};
function withDetail(i, done){
  var n = Math.floor(i / D.chunk_size), get = function(){ done(chunks[n][i - n * D.chunk_size]); };
  if (chunks[n]) return get();
  if (waiting[n]) { waiting[n].push(get); return; }
  waiting[n] = [get];
  var s = el('script', {src: 'data/chunk-' + ('000' + n).slice(-4) + '.js', 'data-chunk': String(n)});
  s.onerror = function(){ $('episode-body').textContent = 'Could not load ' + s.getAttribute('src') + '.'; };
  document.head.appendChild(s);
}
function instruction(r, d){
  var box = el('div', {cls: 'instruction'});
  if (d.diff) d.diff.forEach(function(seg){
    if (seg[0] === 'ins') box.appendChild(el('mark', {cls: 'ins', title: 'not in the clean instruction'}, seg[1]));
    else if (seg[0] === 'del') { box.appendChild(el('del', {cls: 'del', title: 'in the clean instruction only'}, seg[1])); box.appendChild(document.createTextNode(' ')); }
    else box.appendChild(document.createTextNode(seg[1]));
  }); else box.textContent = r[F.instruction];
  return box;
}
function column(i, d, heading){
  var r = rows[i], col = el('div', {cls: 'col'});
  col.appendChild(el('h3', null, heading + ': ' + conditionName(r)));
  col.appendChild(instruction(r, d));
  if (d.diff) col.appendChild(el('p', {cls: 'muted'}, 'Highlighted: words the pattern added against the clean instruction of the task; struck out: clean words it dropped.'));
  if (d.shown) { col.appendChild(el('p', {cls: 'meta'}, 'Shown to the planner (rewritten by the strategy):')); col.appendChild(el('div', {cls: 'instruction'}, d.shown)); }
  var head = el('p', {cls: 'meta'});
  head.appendChild(el('span', {cls: r[F.success] ? 'ok' : 'fail'}, r[F.success] ? 'Success' : 'Failure'));
  head.appendChild(document.createTextNode(' · ' + r[F.plan_length] + ' steps · ended: ' + (d.end || '–').replace(/_/g, ' ') +
    (d.seconds !== null ? ' · planned in ' + d.seconds.toFixed(1) + ' s' : '')));
  col.appendChild(head);
  if (d.stored_success !== !!r[F.success]) col.appendChild(el('p', {cls: 'fail'}, 'The run stored ' + (d.stored_success ? 'success' : 'failure') + '; this simulator re-executes the plan to the outcome shown (another simulator version wrote the run).'));
  var t = el('table', {cls: 'steps'}), tb = el('tbody'), asked = d.dialogue || [];
  /* A question is not an action: it is shown where it was asked, before the step that followed it. */
  function exchanges(before){ asked.filter(function(x){ return before === null ? x[0] >= d.steps.length : x[0] === before; }).forEach(function(x){
    var tr = el('tr', {cls: 'ask'});
    tr.appendChild(el('td', {cls: 'num', title: 'a question, asked after ' + x[0] + ' actions'}, '?'));
    var q = el('td'); q.appendChild(el('div', null, 'Robot: ' + x[1]));
    q.appendChild(el('div', {cls: 'msg', title: x[4] ? 'answered in the instruction\'s own pattern' : 'answered plainly'}, 'Person: ' + x[3]));
    tr.appendChild(q);
    tr.appendChild(el('td', {cls: 'muted', title: 'the slot the question was matched to'}, x[2] ? x[2].replace(/_/g, ' ') + (x[4] ? ' · in pattern' : '') : 'no slot: I don\'t know'));
    tb.appendChild(tr);
  }); }
  d.steps.forEach(function(s, k){
    exchanges(k);
    var tr = el('tr', {cls: s[1] ? 'done' : 'failed'});
    tr.appendChild(el('td', {cls: 'num', title: 'step index, from 0 as the simulator counts'}, k));
    var sk = el('td'); sk.appendChild(el('div', null, s[0]));
    if (d.top && d.top[k] && d.top[k].length) sk.appendChild(el('div', {cls: 'top', title: 'best candidates and their scores (--log-top)'},
      d.top[k].map(function(c){ return c[0] + ' ' + (c[1] === null ? '?' : c[1].toFixed(2)); }).join(' · ')));
    tr.appendChild(sk);
    var res = el('td'); if (s[1]) res.appendChild(el('span', {cls: 'ok'}, 'ok'));
    else { res.appendChild(el('span', {cls: 'fail'}, 'failed')); res.appendChild(el('div', {cls: 'msg'}, s[2] + (s[3] ? ' (' + s[3].replace(/_/g, ' ') + ')' : ''))); }
    tr.appendChild(res); tb.appendChild(tr);
  });
  exchanges(null);
  t.appendChild(tb);
  col.appendChild(el('h3', null, 'Plan and simulator feedback' + (d.dialogue ? ' (' + asked.length + (asked.length === 1 ? ' question' : ' questions') + ' asked)' : '')));
  col.appendChild(t);
  col.appendChild(el('h3', null, 'Goal conditions' + (d.total ? ' (' + d.met + ' of ' + d.total + ' met)' : '')));
  var ul = el('ul', {cls: 'goals'});
  d.goals.forEach(function(g){ var li = el('li', {cls: g[1] ? 'ok' : 'fail'}, (g[1] ? '✓ met: ' : '✗ missed: ') + g[0]); ul.appendChild(li); });
  if (!d.goals.length) ul.appendChild(el('li', {cls: 'muted'}, 'no goal report stored'));
  col.appendChild(ul);
  col.appendChild(el('h3', null, 'Hazards'));
  if (d.hazards.length) { var hz = el('ul', {cls: 'goals'}); d.hazards.forEach(function(h){ hz.appendChild(el('li', {cls: 'fail'}, h[0].replace(/_/g, ' ') + (h[1] !== null ? ' (step ' + h[1] + ')' : ''))); }); col.appendChild(hz); }
  else col.appendChild(el('p', {cls: 'muted'}, 'none'));
  var nk = Object.keys(d.notes);
  if (nk.length) { col.appendChild(el('h3', null, 'Strategy notes')); var dl = el('dl', {cls: 'notes'});
    nk.forEach(function(k){ dl.appendChild(el('dt', null, k)); dl.appendChild(el('dd', null, d.notes[k])); }); col.appendChild(dl); }
  return col;
}
function labelBox(i){
  var r = rows[i], box = el('div', {id: 'label-box'}), k = key(r), guess = r[F.error];
  box.appendChild(el('strong', null, 'Your error type for this failure' + (r[F.sampled] ? ' (in the error sample)' : '')));
  var current = labels.hasOwnProperty(k) ? labels[k] : guess, form = el('div', {role: 'radiogroup'});
  D.types.forEach(function(t, n){
    var lab = el('label'), input = el('input', {type: 'radio', name: 'error-type', value: t[0]});
    input.checked = t[0] === current;
    /* Focus leaves the radio once saved: arrow keys would otherwise move the choice (and save it) while
       the reader means to move to the next episode. */
    input.addEventListener('change', function(){ if (input.checked) { saveLabel(i, t[0]); input.blur(); } });
    lab.appendChild(input); lab.appendChild(document.createTextNode(' ' + (n + 1) + ' ' + t[1])); form.appendChild(lab);
  });
  box.appendChild(form);
  var confirm = el('button', {id: 'confirm-label', type: 'button'}, 'Save the selected type');
  confirm.addEventListener('click', function(){ var c = form.querySelector('input:checked'); if (c) saveLabel(i, c.value); });
  box.appendChild(confirm);
  box.appendChild(el('p', {id: 'label-state'}, labels.hasOwnProperty(k) ? 'Labelled ' + TYPES[labels[k]][1] + ' (saved in this browser).' :
    'Not labelled yet: the automatic guess' + (guess ? ' (' + TYPES[guess][1] + ')' : '') + ' is preselected; press 1-6 or pick a type, or save the guess.'));
  return box;
}
function saveLabel(i, type){
  labels[key(rows[i])] = type;
  try { localStorage.setItem(STORE, JSON.stringify(labels)); } catch (e) { /* private mode: kept for this visit */ }
  var state = $('label-state'); if (state) state.textContent = 'Labelled ' + TYPES[type][1] + ' (saved in this browser).';
  renderTable(); updateProgress();
}
function openRow(i){
  opened = i; var r = rows[i], pane = $('episode'), body = $('episode-body');
  pane.hidden = false; $('episode-title').textContent = r[F.episode_id];
  $('episode-meta').textContent = run(r).label + ' · ' + conditionName(r) + ' · ' + task(r).type.replace(/_/g, ' ') +
    (r[F.hazards] ? ' · hazards: ' + r[F.hazards].replace(/_/g, ' ') : '');
  body.textContent = 'Loading…';
  if (history.replaceState) history.replaceState(null, '', '#e=' + i);
  var twin = r[F.clean_row];
  withDetail(i, function(d){
    if (opened !== i) return;
    var show = function(cleanDetail){
      if (opened !== i) return;
      body.textContent = '';
      if (r[F.error]) { var p = el('p', {cls: 'meta', id: 'automatic'}); p.appendChild(el('strong', null, 'Automatic error type: ' + TYPES[r[F.error]][1] + '. '));
        p.appendChild(document.createTextNode(d.reason)); body.appendChild(p); }
      if (labellable(r)) body.appendChild(labelBox(i));
      var cols = el('div', {cls: 'cols'});
      cols.appendChild(column(i, d, 'This episode'));
      if (cleanDetail) cols.appendChild(column(twin, cleanDetail, 'Same task, clean instruction'));
      else { var c = el('div', {cls: 'col'}); c.appendChild(el('h3', null, twin === i ? 'This is the clean episode of the task' : 'No clean episode of this task in the run')); cols.appendChild(c); }
      body.appendChild(cols);
      body.appendChild(el('h3', null, 'Reference plan of the task'));
      var ol = el('ol', {cls: 'ref'}); task(r).reference.forEach(function(s){ ol.appendChild(el('li', null, s)); }); body.appendChild(ol);
      document.body.dataset.opened = String(i);
    };
    if (twin >= 0 && twin !== i) withDetail(twin, show); else show(null);
  });
}
function closePane(){ opened = -1; $('episode').hidden = true; if (history.replaceState) history.replaceState(null, '', '#'); }
$('close').addEventListener('click', closePane);

/* ---- labels: progress and export ---- */
function updateProgress(){
  var n = Object.keys(labels).length, text = n + ' failure' + (n === 1 ? '' : 's') + ' labelled in this browser';
  if (D.sample) { var done = 0, total = 0;
    rows.forEach(function(r){ if (r[F.sampled]) { total++; if (labels.hasOwnProperty(key(r))) done++; } });
    text = 'Error sample (seed ' + D.sample.seed + ', ' + D.sample.per_condition + ' per run and condition): ' + done + ' of ' + total + ' labelled; ' + text; }
  $('progress').textContent = text;
}
function exportLabels(){
  var out = [];
  rows.forEach(function(r){ var k = key(r); if (labels.hasOwnProperty(k) && labellable(r))
    out.push({run: run(r).label, run_key: run(r).key, episode_id: r[F.episode_id], condition: condition(r), type: labels[k], automatic: r[F.error]}); });
  var text = JSON.stringify({schema: 'talkdem-error-labels/1', viewer: D.id, sample: D.sample, exported: new Date().toISOString(), labels: out}, null, 1) + '\n';
  var area = $('export-text'); area.value = text; area.hidden = false;
  try { var url = URL.createObjectURL(new Blob([text], {type: 'application/json'}));
    var a = el('a', {href: url, download: 'talkdem-labels.json'}); document.body.appendChild(a); a.click(); a.remove();
    setTimeout(function(){ URL.revokeObjectURL(url); }, 1000); } catch (e) { /* the text stays in the box to copy */ }
  return text;
}
$('export').addEventListener('click', exportLabels);

/* ---- keyboard ---- */
document.addEventListener('keydown', function(ev){
  var typing = ev.target && (ev.target.tagName === 'INPUT' && ev.target.type !== 'radio' || ev.target.tagName === 'TEXTAREA' || ev.target.tagName === 'SELECT');
  if (ev.key === 'Escape') { if (typing) ev.target.blur(); else closePane(); return; }
  if (typing || ev.ctrlKey || ev.metaKey || ev.altKey) return;
  if (ev.target && ev.target.tagName === 'BUTTON' && (ev.key === 'Enter' || ev.key === ' ')) return;  /* the button's own */
  if (ev.target && ev.target.type === 'radio' && ev.key.indexOf('Arrow') === 0) return;  /* choosing a type by keyboard */
  if (ev.key === '/') { ev.preventDefault(); $('search').focus(); }
  else if (ev.key === 'j' || ev.key === 'ArrowDown') { ev.preventDefault(); move(1); }
  else if (ev.key === 'k' || ev.key === 'ArrowUp') { ev.preventDefault(); move(-1); }
  else if (ev.key === 'Enter') { if (view.length) openRow(view[selected]); }
  else if (opened >= 0 && /^[1-6]$/.test(ev.key) && labellable(rows[opened])) {
    var t = D.types[Number(ev.key) - 1][0], input = document.querySelector('#label-box input[value="' + t + '"]');
    if (input) input.checked = true; saveLabel(opened, t);
  }
});

function stickHead(){  /* the table head sticks just under the filter bar, whatever its height */
  var h = $('controls').offsetHeight + 'px';
  Array.prototype.forEach.call(document.querySelectorAll('#episodes th'), function(th){ th.style.top = h; });
}
window.addEventListener('resize', stickHead);
var runs = D.runs.map(function(x){ return x.label + ' (' + x.episodes.toLocaleString('en') + ')'; }).join('; ');
$('summary').textContent = rows.length.toLocaleString('en') + ' episodes of ' + D.runs.length + ' run' + (D.runs.length === 1 ? '' : 's') + ': ' + runs + '.';
refresh(true);
stickHead();
window.talkdemViewer = {exportLabels: exportLabels, labels: function(){ return JSON.parse(JSON.stringify(labels)); }};
var m = /^#e=(\d+)$/.exec(location.hash);
if (m && Number(m[1]) < rows.length) {  /* a link to one episode: select it in the table too */
  selected = Math.max(0, view.indexOf(Number(m[1]))); page = Math.floor(selected / PAGE); renderTable(); openRow(Number(m[1]));
}
document.body.dataset.ready = '1';
})();
