// report.html's findings table: sort by a column (click its header), filter by text,
// severity and kind; a row with a place in the 3-D view turns the view to it.
(function () {
  const table = document.getElementById('findings');
  if (!table) return;
  const body = table.tBodies[0];
  const rows = Array.from(body.rows);
  const text = document.getElementById('filter-text');
  const sev = document.getElementById('filter-severity');
  const kind = document.getElementById('filter-kind');
  const count = document.getElementById('filter-count');
  function apply() {
    const q = (text.value || '').toLowerCase();
    let shown = 0;
    for (const r of rows) {
      const ok = (!q || r.textContent.toLowerCase().includes(q)) &&
        (!sev.value || r.dataset.severity === sev.value) && (!kind.value || r.dataset.kind === kind.value);
      r.hidden = !ok; if (ok) shown++;
    }
    count.textContent = `${shown} of ${rows.length} shown`;
  }
  for (const el of [text, sev, kind]) el.addEventListener('input', apply);
  Array.from(table.tHead.rows[0].cells).forEach((th, col) => {
    th.addEventListener('click', () => {
      const dir = th.dataset.dir === 'asc' ? 'desc' : 'asc';
      for (const other of table.tHead.rows[0].cells) delete other.dataset.dir;
      th.dataset.dir = dir;
      const key = r => r.cells[col].dataset.sort ?? r.cells[col].textContent;
      const num = th.dataset.type === 'number';
      rows.sort((a, b) => {
        const x = key(a), y = key(b);
        const c = num ? (parseFloat(x) || 0) - (parseFloat(y) || 0) : x.localeCompare(y);
        return dir === 'asc' ? c : -c;
      });
      rows.forEach(r => body.appendChild(r));
    });
  });
  window.vmachSelectFinding = (index) => {
    const r = rows.find(x => Number(x.dataset.index) === index);
    if (!r) return;
    rows.forEach(x => x.classList.remove('sel'));
    r.hidden = false; r.classList.add('sel'); r.scrollIntoView({ block: 'center' });
  };
  for (const r of rows) r.addEventListener('click', () => {
    rows.forEach(x => x.classList.remove('sel')); r.classList.add('sel');
    if (window.vmachFocus) window.vmachFocus(Number(r.dataset.index));
  });
  apply();
})();
