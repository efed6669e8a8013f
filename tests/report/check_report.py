"""Opens a demsweep HTML report in headless Chromium (driven by Playwright) and reports, as JSON on
stdout, what a person would see: console errors, network requests, the answer at the top (the
first section, whether it shows without scrolling, its grid points, the reference point's verdict), table rows, whether a click on a
column header sorts the rows, the point table's header groups and the columns under them, every
chart's rendered size, whether each run link leads to a visible section, first-paint and sort
timings, and (with --screenshot FILE) a screenshot of the top of the page.

With --results FILE (the results the report was written from), each run's frame player is also
checked: stepping forward and back changes the frame and its time label, playing advances it, and
the disks drawn for a frame sit where h5py reads that frame's positions and radii in the file.

Usage: check_report.py REPORT.html [--results RESULTS.h5] [--screenshot FILE]
"""

import json
import shutil
import sys
import time

from playwright.sync_api import sync_playwright


def chromium_path():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    sys.exit("no Chromium on PATH (CI installs Debian's chromium: apt-get install chromium)")


def numeric(text):
    try:
        return float(text.strip().split()[0].replace("\u2212", "-"))
    except (ValueError, IndexError):
        return None


def option(name):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else None


def stored_disks(results, run_id, name):
    """x, y and r of a player frame (`frame_<k>` or `final`) of run `run_id` as h5py reads them from
    the file (the path of the run's group is /summary's `group` column; frames are (time, disk)
    arrays)."""
    import h5py

    with h5py.File(results, "r") as f:
        ids = list(f["summary/run_id"].asstr()[()])
        run = f[f["summary/group"].asstr()[ids.index(run_id)]]
        if name == "final":
            return run["final"]["x"][:], run["final"]["y"][:], run["final"]["r"][:]
        k = int(name.split("_")[1])
        return run["frames/x"][k], run["frames/y"][k], run["frames/r"][k]


def check_player(page, player, results):
    """What a player shows and whether its frames match the stored ones (see the module doc)."""
    canvas = player.locator("canvas")
    label = player.locator(".time")
    frame = lambda: int(canvas.get_attribute("data-frame"))
    data = player.evaluate("p => JSON.parse(p.querySelector('.player-data').textContent)")
    seen = {"run": player.get_attribute("data-run"), "frames": len(data["frames"]), "first_frame": frame()}
    labels = [label.inner_text()]
    player.locator(".step").click()
    seen["after_step"] = frame()
    labels.append(label.inner_text())
    player.locator(".back").click()
    seen["after_back"] = frame()
    labels.append(label.inner_text())
    seen["labels"] = labels
    player.locator(".play").click()
    page.wait_for_timeout(700)
    seen["after_play"] = frame()
    player.locator(".play").click()
    errors, painted, disks = [], [], 0
    last = len(data["frames"]) - 1
    for k in sorted({0, 1, last // 2, last}):
        player.locator(".scrub").evaluate(f"s => {{ s.value = '{k}'; s.dispatchEvent(new Event('input')); }}")
        drawn = canvas.evaluate("c => c.drawnDisks")
        x, y, r = stored_disks(results, player.get_attribute("data-run"), data["frames"][k]["name"])
        height, ppm, margin = canvas.evaluate("c => c.height"), data["ppm"], data["margin"]
        expected = [(margin + xi * ppm, height - margin - yi * ppm, ri * ppm) for xi, yi, ri in zip(x, y, r)]
        disks = len(expected)
        errors.append(
            max(abs(a - b) for d, e in zip(drawn, expected) for a, b in zip(d, e)) if len(drawn) == disks else None
        )
        # The canvas itself: the pixel at each disk's centre is painted (a disk or a force chain on it).
        painted.append(
            canvas.evaluate(
                """(c, disks) => { const g = c.getContext('2d'); return disks.filter(d => {
                    const p = g.getImageData(Math.round(d[0]), Math.round(d[1]), 1, 1).data;
                    return !(p[0] === 255 && p[1] === 255 && p[2] === 255); }).length / disks.length; }""",
                drawn,
            )
        )
    seen.update({"disks": disks, "max_error_px": errors, "painted_centres": painted})
    return seen


def main():
    report = sys.argv[1]
    screenshot = option("--screenshot")
    results = option("--results")
    out = {"console_errors": [], "requests": []}
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium_path(), args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.on("console", lambda m: out["console_errors"].append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: out["console_errors"].append(str(e)))
        page.on("request", lambda r: out["requests"].append(r.url))
        url = "file://" + report
        start = time.time()
        page.goto(url, wait_until="load")
        out["load_s"] = time.time() - start
        paint = page.evaluate(
            "() => performance.getEntriesByType('paint').map(e => [e.name, e.startTime])"
        )
        out["first_paint_ms"] = dict(paint).get("first-contentful-paint")
        out["first_section"] = page.evaluate("() => document.querySelector('main h2') && document.querySelector('main h2').id")
        answer = page.locator("#verdict + p.verdict")
        box = answer.bounding_box() if answer.count() else None
        out["verdict_in_first_screen"] = box is not None and box["y"] + box["height"] <= 900
        # The first answer: the paragraph right under the heading, as text.
        out["answer"] = answer.inner_text() if answer.count() else None
        out["answer_id"] = answer.get_attribute("id") if answer.count() else None
        out["stray_markup"] = [bit for bit in ("/p>", "<p", "</") if bit in page.inner_text("body")]
        verdict_rows = page.locator("table.verdict:not(#reference-table) tbody tr")
        out["verdict_points"] = [
            [verdict_rows.nth(k).locator("td").nth(c).inner_text() for c in range(2)] for k in range(verdict_rows.count())
        ]
        # The reference point's verdict: the h2 of the section holding it, its text and its rows
        # (grid point, pile decision).
        out["reference_section"] = page.evaluate(
            """() => { const r = document.querySelector('#reference-verdict'); if (!r) return null;
               let h = r.previousElementSibling; while (h && h.tagName !== 'H2') h = h.previousElementSibling;
               return h && h.id; }"""
        )
        reference = page.locator("#reference-verdict")
        out["reference_verdict"] = reference.inner_text() if reference.count() else None
        reference_rows = page.locator("#reference-table tbody tr")
        out["reference_rows"] = [
            [reference_rows.nth(k).locator("td").first.inner_text(), reference_rows.nth(k).locator("td").last.inner_text()]
            for k in range(reference_rows.count())
        ]
        out["points_table_scrolls_sideways"] = page.evaluate(
            "() => { const s = document.querySelector('.scroll'); return !!s && s.scrollWidth > s.clientWidth; }"
        )

        # The column picker: the groups shown at first, then one more ticked on (its columns shown,
        # the table still without sideways scroll or not), then off again.
        visible_columns = lambda: page.evaluate(
            "() => [...document.querySelectorAll('table#points thead tr.columns th')].filter(h => !h.hidden).map(h => h.innerText.trim())"
        )
        boxes = page.locator("#column-groups input[type=checkbox]")
        out["column_groups"] = [[boxes.nth(k).get_attribute("value"), boxes.nth(k).is_checked()] for k in range(boxes.count())]
        out["visible_columns"] = visible_columns()
        off = next((k for k in range(boxes.count()) if not boxes.nth(k).is_checked()), None)
        if off is not None:
            boxes.nth(off).check()
            out["toggled_group"] = boxes.nth(off).get_attribute("value")
            out["visible_columns_toggled"] = visible_columns()
            out["cells_per_row_toggled"] = page.evaluate(
                "() => document.querySelector('table#points tbody tr:not(.spacer)').cells.length"
            )
            boxes.nth(off).uncheck()
            out["visible_columns_untoggled"] = visible_columns()

        table = page.locator("table#points")
        out["rows"] = int(table.get_attribute("data-rows"))
        out["rows_in_page"] = table.locator("tbody tr:not(.spacer)").count()
        headers = table.locator("thead tr.columns th")
        out["columns"] = [headers.nth(k).inner_text().strip() for k in range(headers.count())]
        # Sort by the first numeric column (after the swept values): click, read it back.
        column = next(
            (k for k in range(headers.count()) if headers.nth(k).get_attribute("data-kind") == "number"), None
        )
        out["sorted_column"] = out["columns"][column] if column is not None else None
        if column is not None:
            cells = lambda: table.locator(f"tbody tr:not(.spacer) td:nth-child({column + 1})").all_inner_texts()
            start = time.time()
            headers.nth(column).click()
            page.wait_for_function("() => document.querySelector('table#points').dataset.sorted !== undefined")
            out["sort_s"] = time.time() - start
            out["sort_ms"] = page.evaluate("() => Number(document.querySelector('table#points').dataset.sortMs)")
            values = [v for v in map(numeric, cells()) if v is not None]
            out["sorted_ascending"] = values == sorted(values) and len(values) > 1
            headers.nth(column).click()
            page.wait_for_function(
                "() => document.querySelector('table#points').dataset.sorted.endsWith('desc')"
            )
            values = [v for v in map(numeric, cells()) if v is not None]
            out["sorted_descending"] = values == sorted(values, reverse=True) and len(values) > 1

        # Scrolled to the end, a long table draws its last rows (no spacer below them).
        page.evaluate("() => { const s = document.querySelector('.scroll'); s.scrollTop = s.scrollHeight; }")
        page.wait_for_timeout(200)
        out["bottom_reached"] = page.evaluate(
            "() => !document.querySelector('table#points tbody').lastElementChild.classList.contains('spacer')"
        )

        charts = page.locator("svg")
        sizes = [charts.nth(k).bounding_box() for k in range(charts.count())]
        out["charts"] = len(sizes)
        out["charts_without_size"] = sum(1 for b in sizes if not b or b["width"] <= 0 or b["height"] <= 0)

        links = page.locator("table#points a.run")
        out["run_links"] = links.count()
        reached = 0
        for k in range(min(links.count(), 5)):
            link = links.nth(k)
            target = link.get_attribute("href")
            link.click()
            section = page.locator(target)
            if page.evaluate("() => location.hash") == target and section.is_visible():
                reached += 1
        out["run_links_reached"] = reached

        status = page.locator("select#status-filter")
        if status.count():
            options = status.locator("option").all_inner_texts()
            out["status_options"] = options
        headers = page.locator("table#points thead tr.groups th")
        out["header_groups"] = [
            [headers.nth(k).inner_text().strip(), int(headers.nth(k).get_attribute("colspan") or 1)]
            for k in range(headers.count())
        ]
        if results:
            players = page.locator(".player")
            out["players"] = [check_player(page, players.nth(k), results) for k in range(min(players.count(), 3))]
            out["player_count"] = players.count()
        if screenshot:
            page.set_viewport_size({"width": 1280, "height": 2200})
            page.goto(url, wait_until="load")
            page.screenshot(path=screenshot, full_page=False)
        browser.close()
    out["requests"] = [u for u in out["requests"] if u != url and not u.startswith("data:")]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
