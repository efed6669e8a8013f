// demsweep report: builds the per-point table from the embedded JSON, sorts it by any column
// (click a header; again to reverse) and filters it by run status. No network, no libraries.
// Up to WINDOW rows are in the page at once: a longer table renders the rows scrolled into view
// (between two spacer rows of the height of the others), so that sorting 10 000 points stays fast.
//
// Data: { columns: [{ name, kind: "text" | "number" | "run", unit }], rows: [{ statuses, cells }] };
// a number cell is a value or [mean, 95 % half-width], a text cell a string, a run cell
// [id of a run with a section of its own or null, the point's run ids], a missing value null.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("points-data").textContent);
  var table = document.getElementById("points");
  var body = table.tBodies[0];
  var headers = table.tHead.rows[0].cells;
  var filter = document.getElementById("status-filter");
  var scroller = table.parentElement;
  var order = data.rows.map(function (_, i) { return i; });
  var shown = order;
  var sortColumn = -1, descending = false;
  var WINDOW = 400, rowHeight = 24, drawnFirst = -1;

  function escape(text) {
    return String(text).replace(/[&<>"]/g, function (c) {
      return { "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c];
    });
  }

  function number(x) {
    if (x === 0) return "0";
    var a = Math.abs(x);
    return a >= 1e-3 && a < 1e6 ? String(Number(x.toPrecision(4))) : x.toExponential(3);
  }

  function cell(value, column) {
    if (value === null || value === undefined) return "<td class=\"missing\">\u2013</td>";
    if (column.kind === "run") {
      // The charted run (or the first), and how many more; every id in the tooltip.
      var ids = value[1].split(" ");
      var shown = value[0] === null ? escape(ids[0]) :
        "<a class=\"run\" href=\"#run-" + escape(value[0]) + "\">" + escape(value[0]) + "</a>";
      var more = ids.length > 1 ? " +" + (ids.length - 1) : "";
      return "<td class=\"runs\" title=\"" + escape(value[1]) + "\">" + shown + more + "</td>";
    }
    if (column.kind === "text") return "<td>" + escape(value) + "</td>";
    var text = Array.isArray(value) ? number(value[0]) + (value[1] === null ? "" : " \u00b1 " + number(value[1])) : number(value);
    return "<td class=\"num\">" + text + (column.unit ? " " + escape(column.unit) : "") + "</td>";
  }

  function spacer(rows) {
    return rows > 0 ? "<tr class=\"spacer\" style=\"height:" + rows * rowHeight + "px\"><td colspan=\"" +
      data.columns.length + "\"></td></tr>" : "";
  }

  // Draws the rows of `shown` around the scroll position (all of them in a short table).
  function draw(force) {
    var first = 0;
    if (shown.length > WINDOW) {
      var top = Math.floor(scroller.scrollTop / rowHeight);
      first = Math.max(0, Math.min(shown.length - WINDOW, top - WINDOW / 4));
      if (!force && drawnFirst >= 0 && Math.abs(first - drawnFirst) < WINDOW / 4) return;
    }
    var last = Math.min(shown.length, first + WINDOW);
    var html = [spacer(first)];
    for (var k = first; k < last; k++) {
      var row = data.rows[shown[k]];
      var cells = [];
      for (var c = 0; c < data.columns.length; c++) cells.push(cell(row.cells[c], data.columns[c]));
      html.push("<tr>" + cells.join("") + "</tr>");
    }
    html.push(spacer(shown.length - last));
    body.innerHTML = html.join("");
    drawnFirst = first;
    // Spacers must match the rows' real height, or scrolling would jump: measure, redraw once.
    var sample = body.querySelector("tr:not(.spacer)");
    var measured = sample ? sample.getBoundingClientRect().height : 0;
    if (measured > 0 && Math.abs(measured - rowHeight) > 0.01) {
      rowHeight = measured;
      if (shown.length > WINDOW) draw(true);
    }
  }

  function render() {
    var wanted = filter ? filter.value : "";
    shown = wanted ? order.filter(function (i) { return data.rows[i].statuses.indexOf(wanted) >= 0; }) : order;
    table.dataset.rows = String(shown.length);
    draw(true);
  }

  function key(row, column) {
    var value = data.rows[row].cells[column];
    if (value === null || value === undefined) return null;
    if (data.columns[column].kind === "run") return value[1];
    return Array.isArray(value) ? value[0] : value;
  }

  function sortBy(column) {
    var start = performance.now();
    descending = column === sortColumn ? !descending : false;
    sortColumn = column;
    order.sort(function (a, b) {
      var x = key(a, column), y = key(b, column);
      if (x === null || y === null) return x === null ? (y === null ? a - b : 1) : -1;
      var c = x < y ? -1 : x > y ? 1 : a - b;
      return descending ? -c : c;
    });
    render();
    for (var h = 0; h < headers.length; h++) headers[h].removeAttribute("aria-sort");
    headers[column].setAttribute("aria-sort", descending ? "descending" : "ascending");
    table.dataset.sortMs = String(performance.now() - start);
    table.dataset.sorted = data.columns[column].name + (descending ? " desc" : " asc");
  }

  for (var h = 0; h < headers.length; h++) headers[h].addEventListener("click", sortBy.bind(null, h));
  if (filter) filter.addEventListener("change", render);
  scroller.addEventListener("scroll", function () { draw(false); }, { passive: true });
  render();
})();
