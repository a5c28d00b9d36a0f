/* The sample page's filters: every task and utterance is already in the markup; this only hides what the
   pattern, level, task type and search do not select. */
(function(){
  'use strict';
  var $ = function(id){ return document.getElementById(id); };
  var tasks = Array.prototype.slice.call(document.querySelectorAll('section.task'));
  /* Searched without case, over what a reader sees of the task (its id, seed, clean control, variants). */
  var haystacks = tasks.map(function(s){ return s.textContent.toLowerCase(); });
  function apply(){
    var pattern = $('f-pattern').value, level = $('f-level').value, type = $('f-type').value;
    var query = $('search').value.trim().toLowerCase(), shown = 0;
    tasks.forEach(function(section, i){
      var visible = (!type || section.dataset.type === type) && (!query || haystacks[i].indexOf(query) >= 0);
      section.hidden = !visible;
      if (visible) shown += 1;
      section.querySelectorAll('tr[data-pattern]').forEach(function(row){
        row.hidden = Boolean(pattern) && row.dataset.pattern !== pattern;
      });
      section.querySelectorAll('[data-level]').forEach(function(cell){
        cell.hidden = Boolean(level) && cell.dataset.level !== level;
      });
    });
    $('count').textContent = shown + ' of ' + tasks.length + ' tasks';
    $('none').hidden = shown > 0;
  }
  ['f-pattern', 'f-level', 'f-type'].forEach(function(id){ $(id).addEventListener('change', apply); });
  $('search').addEventListener('input', apply);
  apply();
  document.body.dataset.ready = '1';
})();
