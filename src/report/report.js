// demsweep report: builds the per-point table from the embedded JSON, sorts it by any column
// (click a header; again to reverse) and filters it by run status. No network, no libraries.
// Up to WINDOW rows are in the page at once: a longer table renders the rows scrolled into view
// (between two spacer rows of the height of the others), so that sorting 10 000 points stays fast.
// A check box per header group shows or hides its columns (`shown_groups` at first), so that the
// table fits the page's width; every column stays one click away.
//
// Data: { columns: [{ name, kind: "text" | "number" | "run", unit, description, group }],
// rows: [{ statuses, cells }], shown_groups: [group] } (units and groups are in the header, not repeated in the cells);
// a number cell is a value or [mean, 95 % half-width], a text cell a string, a run cell
// [id of a run with a section of its own or null, the point's run ids], a missing value null.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("points-data").textContent);
  var table = document.getElementById("points");
  var body = table.tBodies[0];
  var headers = table.tHead.rows[table.tHead.rows.length - 1].cells;
  var filter = document.getElementById("status-filter");
  var scroller = table.parentElement;
  var order = data.rows.map(function (_, i) { return i; });
  var shown = order;
  var sortColumn = -1, descending = false;
  var WINDOW = 400, rowHeight = 24, drawnFirst = -1;
  var groupHeaders = table.tHead.rows[0].cells;
  var groups = [], shownGroups = {}, visible = [];
  data.columns.forEach(function (column) {
    if (groups.indexOf(column.group) < 0) groups.push(column.group);
  });
  (data.shown_groups || groups).forEach(function (group) { shownGroups[group] = true; });

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

  // mean ± half-width, rounded to the half-width's second significant digit (as the Rust side's
  // stats::points::plus_minus), in a power of ten outside [1e-3, 1e6).
  function plusMinus(m, h) {
    var size = Math.max(Math.abs(m), h);
    var scale = size === 0 || (size >= 1e-3 && size < 1e6) ? 0 : Math.floor(Math.log10(size));
    var step = h > 0 ? h : size * 1e-4;
    if (!(step > 0)) return number(m) + " \u00b1\u00a00";
    var digit = Math.floor(Math.log10(step / Math.pow(10, scale))) - 1;
    function at(x) {
      var unit = Math.pow(10, digit);
      return (Math.round(x / Math.pow(10, scale) / unit) * unit + 0).toFixed(Math.max(0, -digit));
    }
    var text = at(m) + " \u00b1\u00a0" + at(h);
    return scale === 0 ? text : "(" + text + ")e" + scale;
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
    var text = Array.isArray(value) ? (value[1] === null ? number(value[0]) : plusMinus(value[0], value[1])) : number(value);
    return "<td class=\"num\">" + text + "</td>";
  }

  function spacer(rows) {
    return rows > 0 ? "<tr class=\"spacer\" style=\"height:" + rows * rowHeight + "px\"><td colspan=\"" +
      visible.length + "\"></td></tr>" : "";
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
      for (var v = 0; v < visible.length; v++) cells.push(cell(row.cells[visible[v]], data.columns[visible[v]]));
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

  // Shows the columns of the checked groups: their headers, one <colgroup> per group, their cells.
  function showGroups() {
    visible = [];
    data.columns.forEach(function (column, c) {
      var on = !!shownGroups[column.group];
      headers[c].hidden = !on;
      if (on) visible.push(c);
    });
    var old = table.querySelectorAll("colgroup");
    for (var k = 0; k < old.length; k++) old[k].remove();
    groups.forEach(function (group, g) {
      groupHeaders[g].hidden = !shownGroups[group];
      if (!shownGroups[group]) return;
      var span = data.columns.filter(function (column) { return column.group === group; }).length;
      var colgroup = document.createElement("colgroup");
      colgroup.span = span;
      table.insertBefore(colgroup, table.tHead);
    });
    table.dataset.columns = String(visible.length);
    draw(true);
  }

  var picker = document.getElementById("column-groups");
  if (picker) {
    groups.forEach(function (group) {
      var label = document.createElement("label");
      var box = document.createElement("input");
      box.type = "checkbox";
      box.value = group;
      box.checked = !!shownGroups[group];
      box.addEventListener("change", function () { shownGroups[group] = box.checked; showGroups(); });
      label.appendChild(box);
      label.appendChild(document.createTextNode(" " + group));
      picker.appendChild(label);
    });
  }

  for (var h = 0; h < headers.length; h++) headers[h].addEventListener("click", sortBy.bind(null, h));
  if (filter) filter.addEventListener("change", render);
  scroller.addEventListener("scroll", function () { draw(false); }, { passive: true });
  showGroups();
  render();
})();

// Frame players: a charted run's deposition from its stored frames (see src/report/player.rs for the
// data). The disks are drawn to scale in the box, the force chains over them (width proportional to
// the normal force); play/pause, step back and forth, or drag the slider. After each drawing the
// canvas keeps what it drew (`drawnDisks`: [x, y, radius] in canvas pixels) and `data-frame`.
(function () {
  "use strict";
  var DISK = "#8fb3d9", OUTLINE = "#3b5b80", CHAIN = "rgb(160, 0, 0)", WALL = "#000";
  var FRAME_MS = 250, CHAIN_WIDTH = 0.6;

  function setUp(player) {
    var data = JSON.parse(player.querySelector(".player-data").textContent);
    var canvas = player.querySelector("canvas");
    var context = canvas.getContext("2d");
    var play = player.querySelector(".play"), scrub = player.querySelector(".scrub");
    var label = player.querySelector(".time");
    var u = data.unit, ppm = data.ppm, m = data.margin;
    var px = function (x) { return m + x * u * ppm; };
    var py = function (y) { return canvas.height - m - y * u * ppm; };
    var smallest = Math.min.apply(null, data.r.length ? data.r : [0]) * u * ppm;
    var current = 0, timer = null;

    function draw(k) {
      var frame = data.frames[k], xy = frame.xy, drawn = [];
      context.fillStyle = "#fff";
      context.fillRect(0, 0, canvas.width, canvas.height);
      context.strokeStyle = WALL;
      context.lineWidth = 3;
      context.beginPath();
      context.moveTo(px(0), py(data.box[1] / u));
      context.lineTo(px(0), py(0));
      context.lineTo(px(data.box[0] / u), py(0));
      context.lineTo(px(data.box[0] / u), py(data.box[1] / u));
      context.stroke();
      context.fillStyle = DISK;
      context.strokeStyle = OUTLINE;
      context.lineWidth = 1;
      for (var i = 0; i < data.r.length; i++) {
        var disk = [px(xy[2 * i]), py(xy[2 * i + 1]), data.r[i] * u * ppm];
        context.beginPath();
        context.arc(disk[0], disk[1], Math.max(disk[2] - 0.5, 0.5), 0, 2 * Math.PI);
        context.fill();
        context.stroke();
        drawn.push(disk);
      }
      context.strokeStyle = CHAIN;
      context.lineCap = "round";
      var chain = function (x0, y0, x1, y1, steps) {
        var width = Math.round(CHAIN_WIDTH * 2 * smallest * steps / 1000);
        if (width < 1) return;
        context.lineWidth = width;
        context.beginPath();
        context.moveTo(x0, y0);
        context.lineTo(x1, y1);
        context.stroke();
      };
      for (var p = 0; p + 2 < frame.pairs.length; p += 3) {
        var a = frame.pairs[p], b = frame.pairs[p + 1];
        chain(px(xy[2 * a]), py(xy[2 * a + 1]), px(xy[2 * b]), py(xy[2 * b + 1]), frame.pairs[p + 2]);
      }
      for (var w = 0; w + 3 < frame.walls.length; w += 4) {
        var d = frame.walls[w];
        chain(px(xy[2 * d]), py(xy[2 * d + 1]), px(frame.walls[w + 1]), py(frame.walls[w + 2]), frame.walls[w + 3]);
      }
      current = k;
      scrub.value = String(k);
      label.textContent = "frame " + (k + 1) + " of " + data.frames.length + ", t = " +
        Number(frame.t.toPrecision(4)) + " s" + (frame.name === "final" ? " (final state)" : "");
      canvas.drawnDisks = drawn;
      canvas.dataset.frame = String(k);
    }

    function pause() {
      if (timer !== null) clearInterval(timer);
      timer = null;
      play.textContent = "play";
    }

    function step(by) {
      pause();
      draw((current + by + data.frames.length) % data.frames.length);
    }

    play.addEventListener("click", function () {
      if (timer !== null) return pause();
      play.textContent = "pause";
      if (current === data.frames.length - 1) draw(0);
      timer = setInterval(function () {
        if (current === data.frames.length - 1) return pause();
        draw(current + 1);
      }, FRAME_MS);
    });
    player.querySelector(".back").addEventListener("click", function () { step(-1); });
    player.querySelector(".step").addEventListener("click", function () { step(1); });
    scrub.addEventListener("input", function () { pause(); draw(Number(scrub.value)); });
    draw(0);
  }

  var players = document.querySelectorAll(".player");
  for (var k = 0; k < players.length; k++) setUp(players[k]);
})();
