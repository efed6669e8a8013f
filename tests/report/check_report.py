"""Opens a demsweep HTML report in headless Chromium (driven by Playwright) and reports, as JSON on
stdout, what a person would see: console errors, network requests, table rows, whether a click on a
column header sorts the rows, every chart's rendered size, whether each run link leads to a visible
section, first-paint and sort timings, and (with --screenshot FILE) a full-page screenshot.

Usage: check_report.py REPORT.html [--screenshot FILE]
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


def main():
    report = sys.argv[1]
    screenshot = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
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

        table = page.locator("table#points")
        out["rows"] = int(table.get_attribute("data-rows"))
        out["rows_in_page"] = table.locator("tbody tr:not(.spacer)").count()
        headers = table.locator("thead th")
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
        if screenshot:
            page.set_viewport_size({"width": 1280, "height": 2200})
            page.goto(url, wait_until="load")
            page.screenshot(path=screenshot, full_page=False)
        browser.close()
    out["requests"] = [u for u in out["requests"] if u != url and not u.startswith("data:")]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
