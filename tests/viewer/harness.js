/* Injected by viewer_browser.drive: helpers for the STEPS a test runs after the viewer loaded. */
window.addEventListener('load', function(){
  var out = {loadedAt: performance.now(), downloads: []};
  /* A download is recorded, not made: what the Export button hands the browser is what the test checks. */
  var click = HTMLAnchorElement.prototype.click;
  HTMLAnchorElement.prototype.click = function(){
    if (!this.hasAttribute('download')) return click.call(this);
    out.downloads.push({name: this.getAttribute('download'), blob: this.href.indexOf('blob:') === 0});
  };
  var $ = function(id){ return document.getElementById(id); };
  function finish(){ var pre = document.createElement('pre'); pre.id = 'measurements';
    pre.textContent = JSON.stringify(out); document.body.appendChild(pre); }
  function waitFor(cond, then, tries){ tries = tries || 0; if (cond()) { try { then(); } catch (e) { out.error = String(e); finish(); } return; }
    if (tries > 400) { out.timeout = true; return finish(); } setTimeout(function(){ waitFor(cond, then, tries + 1); }, 25); }
  function key(k){ document.dispatchEvent(new KeyboardEvent('keydown', {key: k, bubbles: true})); }
  function set(id, value){ var e = $(id); e.value = value;
    e.dispatchEvent(new Event(e.tagName === 'INPUT' ? 'input' : 'change', {bubbles: true})); }
  function rows(){ return Array.from(document.querySelectorAll('#episodes tbody tr')).map(function(tr){
    return {row: Number(tr.dataset.row), id: tr.cells[1].title, cells: Array.from(tr.cells).map(function(td){ return td.textContent; })}; }); }
  function chunksLoaded(){ return Array.from(document.querySelectorAll('script[data-chunk]')).map(function(s){ return Number(s.dataset.chunk); }); }
  function opened(){ return document.body.dataset.opened !== undefined && document.querySelector('#episode-body .steps'); }
  try {
STEPS
  } catch (e) { out.error = String(e); finish(); }
});
