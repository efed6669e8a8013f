//! Charts drawn for the page: SVG documents, with what was noted on the way, and a run's player.

use super::player;
use crate::output::SummaryRow;
use crate::physics::record::Snapshot;
use crate::plot::results::{ChartSink, SvgCharts};
use crate::plot::{Canvas, ChartOptions, PlotError};

/// Size of every chart on the page (pixels; the page scales them to its width).
pub(super) const CHART_SIZE: (u32, u32) = (900, 560);

/// Charts drawn as SVG documents with what was noted on the way, and a run's frame player.
pub(super) struct Svgs {
    pub(super) drawn: SvgCharts,
    pub(super) player: Option<String>,
}

impl Svgs {
    pub(super) fn new() -> Self {
        Self { drawn: SvgCharts::new(CHART_SIZE), player: None }
    }
}

impl ChartSink for Svgs {
    fn chart<T>(
        &mut self,
        name: &str,
        subject: &str,
        draw: impl Fn(&ChartOptions, Canvas<'_>) -> Result<T, PlotError>,
    ) -> Option<T> {
        self.drawn.chart(name, subject, draw)
    }

    fn note(&mut self, text: &str) {
        self.drawn.note(text);
    }

    fn fail(&mut self, error: &PlotError) {
        self.drawn.fail(error);
    }

    fn deposition(&mut self, row: &SummaryRow, box_size: (f64, f64), pictures: &[(String, &Snapshot)]) {
        self.player = Some(player::player(row, box_size, pictures));
    }
}
