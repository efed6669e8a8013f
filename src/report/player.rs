//! The frame player of a charted run: its stored frames as compact JSON inside the page, which
//! `report.js` draws on a canvas (disks to scale in the box, force chains over them) with play,
//! pause, step and a slider, the frame and its simulated time shown.
//!
//! Data (`player-data`): `{ box: [width, height] (m), unit (m), ppm (canvas pixels per metre),
//! margin (pixels), r: [radius / unit], frames: [{ name, t (s), xy: [x / unit, y / unit, …],
//! pairs: [i, j, w, …], walls: [i, x / unit, y / unit, w, …] }] }`: positions and radii as whole
//! multiples of `unit` (the box's larger side over [`RESOLUTION`]); a force chain between disks `i`
//! and `j`, or from disk `i` to its contact point on a wall, has the width `w` in thousandths of the
//! frame's largest normal force ([`FORCE_STEPS`]), the widest as wide as in `demsweep plot`'s pictures.

use serde_json::json;

use super::html::escape;
use crate::output::SummaryRow;
use crate::physics::record::Snapshot;
use crate::plot::results::spread;

/// Frames a player holds at most (spread over the run, the first and the last kept): this bounds
/// the page's size whatever the frame interval.
pub const MAX_FRAMES: usize = 100;
/// Positions and radii are stored as whole multiples of the box's larger side over this.
const RESOLUTION: f64 = 20_000.0;
/// Force-chain widths are stored in this many steps of the frame's largest normal force.
const FORCE_STEPS: f64 = 1000.0;
/// The box is drawn at most this many pixels wide and high (before the margin).
const BOX_PIXELS: (f64, f64) = (860.0, 480.0);
/// Room around the box on the canvas (pixels).
const MARGIN: f64 = 8.0;

/// The player of run `row` in a box of `box_size` (m) over `pictures` (its frames, then its final
/// state; see [`crate::plot::results::ChartSink::deposition`]); with a note when frames were left out.
pub fn player(row: &SummaryRow, box_size: (f64, f64), pictures: &[(String, &Snapshot)]) -> String {
    let (width, height) = box_size;
    let unit = width.max(height) / RESOLUTION;
    let ppm = (BOX_PIXELS.0 / width).min(BOX_PIXELS.1 / height);
    let chosen = spread(pictures.len(), MAX_FRAMES);
    let radii = pictures.first().map(|(_, s)| s.r.iter().map(|&r| whole(r, unit)).collect::<Vec<_>>());
    let frames: Vec<_> = chosen.iter().map(|&k| frame(&pictures[k].0, pictures[k].1, unit)).collect();
    let data = json!({
        "box": [width, height], "unit": unit, "ppm": ppm, "margin": MARGIN,
        "r": radii.unwrap_or_default(), "frames": frames,
    });
    let canvas = (width * ppm + 2.0 * MARGIN, height * ppm + 2.0 * MARGIN);
    let left_out = match chosen.len() < pictures.len() {
        true => format!(
            "<p class=\"note\">{} of {} frames shown ({MAX_FRAMES} at most, spread over the run).</p>",
            chosen.len(),
            pictures.len()
        ),
        false => String::new(),
    };
    format!(
        "<div class=\"player\" data-run=\"{id}\"><h4>Deposition</h4>\
         <canvas width=\"{:.0}\" height=\"{:.0}\"></canvas><div class=\"player-controls\">\
         <button type=\"button\" class=\"play\">play</button><button type=\"button\" class=\"back\" title=\"previous frame\">&#9664;</button>\
         <button type=\"button\" class=\"step\" title=\"next frame\">&#9654;</button>\
         <input type=\"range\" class=\"scrub\" min=\"0\" max=\"{}\" value=\"0\" aria-label=\"frame\">\
         <span class=\"time\"></span></div>{left_out}\
         <script type=\"application/json\" class=\"player-data\">{}</script></div>",
        canvas.0.ceil(),
        canvas.1.ceil(),
        frames.len().saturating_sub(1),
        data.to_string().replace("</", "<\\/"),
        id = escape(&row.id),
    )
}

/// `value` as a whole multiple of `unit` (0 when not finite: the disk is drawn at the origin's corner).
fn whole(value: f64, unit: f64) -> i64 {
    if value.is_finite() { (value / unit).round() as i64 } else { 0 }
}

/// One frame's data: name, time, positions and force chains.
fn frame(name: &str, snapshot: &Snapshot, unit: f64) -> serde_json::Value {
    let xy: Vec<i64> =
        snapshot.x.iter().zip(&snapshot.y).flat_map(|(&x, &y)| [whole(x, unit), whole(y, unit)]).collect();
    let c = &snapshot.contacts;
    let largest = c.normal_force.iter().copied().filter(|f| f.is_finite()).fold(0.0, f64::max);
    let (mut pairs, mut walls) = (Vec::new(), Vec::new());
    for k in 0..c.len() {
        let steps = (FORCE_STEPS * c.normal_force[k] / largest).round();
        if steps.is_nan() || steps < 1.0 {
            continue;
        }
        let (first, second, steps) = (i64::from(c.first[k]), c.second[k], steps as i64);
        match second >= 0 {
            true => pairs.extend([first, second, steps]),
            false => walls.extend([first, whole(c.point_x[k], unit), whole(c.point_y[k], unit), steps]),
        }
    }
    json!({"name": name, "t": snapshot.time, "xy": xy, "pairs": pairs, "walls": walls})
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A snapshot at `time` of two disks, one resting on the floor and pressing on the other.
    fn snapshot(time: f64) -> Snapshot {
        let mut s =
            Snapshot { time, x: vec![0.05, 0.05], y: vec![0.01, 0.03], r: vec![0.01, 0.01], ..Default::default() };
        s.contacts.first = vec![0, 0];
        s.contacts.second = vec![1, -1];
        s.contacts.normal_force = vec![2.0, 4.0];
        s.contacts.point_x = vec![0.05, 0.05];
        s.contacts.point_y = vec![0.02, 0.0];
        s
    }

    /// The player's data, parsed back.
    fn data(html: &str) -> serde_json::Value {
        let start = html.find("player-data\">").unwrap() + "player-data\">".len();
        serde_json::from_str(&html[start..html[start..].find("</script>").unwrap() + start]).unwrap()
    }

    #[test]
    fn frames_keep_positions_to_a_twenty_thousandth_and_chains_in_thousandths_of_the_largest_force() {
        let row = SummaryRow::failed(7, "r0007", &[], "");
        let frames = [snapshot(0.0), snapshot(0.5)];
        let pictures: Vec<(String, &Snapshot)> = vec![("frame_0".into(), &frames[0]), ("final".into(), &frames[1])];
        let html = player(&row, (0.1, 0.2), &pictures);
        assert!(html.contains("data-run=\"r0007\""), "{html}");
        assert!(!html.contains("frames shown"), "no frame left out");
        let data = data(&html);
        let unit = data["unit"].as_f64().unwrap();
        assert_eq!(unit, 0.2 / 20_000.0);
        assert_eq!(data["r"], json!([1000, 1000]));
        assert_eq!(data["frames"][1]["name"], "final");
        assert_eq!(data["frames"][1]["xy"], json!([5000, 1000, 5000, 3000]));
        assert_eq!(data["frames"][1]["pairs"], json!([0, 1, 500]), "half the largest force");
        assert_eq!(data["frames"][1]["walls"], json!([0, 5000, 0, 1000]), "to the contact point on the floor");
    }

    #[test]
    fn a_long_run_shows_at_most_max_frames_spread_over_it_and_says_so() {
        let row = SummaryRow::failed(0, "r0000", &[], "");
        let frames: Vec<Snapshot> = (0..250).map(|k| snapshot(k as f64 * 0.01)).collect();
        let pictures: Vec<(String, &Snapshot)> = frames.iter().map(|s| ("frame".to_string(), s)).collect();
        let html = player(&row, (0.1, 0.2), &pictures);
        let data = data(&html);
        let times: Vec<f64> = data["frames"].as_array().unwrap().iter().map(|f| f["t"].as_f64().unwrap()).collect();
        assert_eq!(times.len(), MAX_FRAMES);
        assert_eq!((times[0], times[MAX_FRAMES - 1]), (0.0, 2.49), "the first and the last kept");
        assert!(html.contains(&format!("{MAX_FRAMES} of 250 frames shown")), "{html}");
    }
}
