//! The SVG flight profile: depth (downward) against time, like the paper's
//! Fig. 2 and 4b, with the script's actions marked.

use plotters::prelude::*;

use crate::simulation::Simulation;

/// A mark on the profile: the script stored a new value in a sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct Action {
    /// Mission seconds.
    pub time: f64,
    pub depth: f64,
    pub label: String,
}

/// Depth over time and the script's actions, recorded cycle by cycle for the plot.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// (mission seconds, depth), one per cycle; f32 keeps a 30-day run small.
    pub points: Vec<(f32, f32)>,
    pub actions: Vec<Action>,
    /// Last value the script stored in each sensor it stored (for "changed" marks).
    last_stored: Vec<(u32, f64)>,
}

/// At most this many action marks (a script that changes a sensor every cycle
/// would otherwise cover the plot).
pub const MAX_ACTIONS: usize = 200;

impl Trace {
    /// Records the finished cycle: call after `finish_cycle`/`step_cycle`.
    pub fn record(&mut self, sim: &Simulation) {
        // The finished cycle ends where the next one starts.
        let time = sim.time();
        let depth = sim.depth();
        if self.points.is_empty() {
            self.points.push((0.0, 0.0));
        }
        self.points.push((time as f32, depth as f32));
        for &id in sim.stored() {
            let value = sim.sensor(id).unwrap_or(f64::NAN);
            let previous = self
                .last_stored
                .iter_mut()
                .find(|(sensor, _)| *sensor == id.0);
            let changed = match previous {
                Some((_, last)) if *last == value => false,
                Some((_, last)) => {
                    *last = value;
                    true
                }
                None => {
                    self.last_stored.push((id.0, value));
                    true
                }
            };
            if changed && self.actions.len() < MAX_ACTIONS {
                let name = sim.sensor_list().name(id).unwrap_or("sensor");
                self.actions.push(Action {
                    time,
                    depth,
                    label: format!("{name}={value}"),
                });
            }
        }
    }
}

/// Renders the trace to an SVG document.
pub fn render_svg(trace: &Trace, title: &str, water_depth: f64) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 560)).into_drawing_area();
        draw(&root, trace, title, water_depth).map_err(|error| error.to_string())?;
        root.present().map_err(|error| error.to_string())?;
    }
    Ok(svg)
}

/// Points to draw: min and max per bucket when the trace is long, so a
/// 30-day run draws in a few thousand segments and still shows every turn.
fn decimate(points: &[(f32, f32)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= buckets * 2 {
        return points.iter().map(|&(t, d)| (t as f64, d as f64)).collect();
    }
    let per_bucket = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(buckets * 2);
    for chunk in points.chunks(per_bucket) {
        let (mut low, mut high) = (chunk[0], chunk[0]);
        let (mut low_at, mut high_at) = (0, 0);
        for (at, point) in chunk.iter().enumerate() {
            if point.1 < low.1 {
                low = *point;
                low_at = at;
            }
            if point.1 > high.1 {
                high = *point;
                high_at = at;
            }
        }
        let (first, second) = if low_at <= high_at {
            (low, high)
        } else {
            (high, low)
        };
        out.push((first.0 as f64, first.1 as f64));
        out.push((second.0 as f64, second.1 as f64));
    }
    out
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    trace: &Trace,
    title: &str,
    water_depth: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let duration = trace
        .points
        .last()
        .map(|p| p.0 as f64)
        .unwrap_or(0.0)
        .max(60.0);
    // Minutes for short runs, hours for long ones.
    let (scale, unit) = if duration > 6.0 * 3600.0 {
        (3600.0, "hours")
    } else {
        (60.0, "minutes")
    };
    let deepest = trace
        .points
        .iter()
        .map(|p| p.1 as f64)
        .fold(0.0, f64::max)
        .max(5.0);
    let bottom = (deepest * 1.1)
        .min(water_depth.max(deepest))
        .max(deepest + 1.0);
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..duration / scale, bottom..0.0)?;
    chart
        .configure_mesh()
        .x_desc(format!("time ({unit})"))
        .y_desc("depth (m)")
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    if water_depth <= bottom {
        chart.draw_series(LineSeries::new(
            [(0.0, water_depth), (duration / scale, water_depth)],
            ShapeStyle::from(&RGBColor(140, 100, 60)).stroke_width(2),
        ))?;
    }
    let points = decimate(&trace.points, 4000);
    chart
        .draw_series(LineSeries::new(
            points.into_iter().map(|(t, d)| (t / scale, d)),
            ShapeStyle::from(&BLUE).stroke_width(2),
        ))?
        .label("depth")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    let red = RGBColor(200, 30, 30);
    chart
        .draw_series(trace.actions.iter().map(|action| {
            EmptyElement::at((action.time / scale, action.depth))
                + Circle::new((0, 0), 5, ShapeStyle::from(&red).filled())
                + Text::new(
                    action.label.clone(),
                    (9, -6),
                    ("sans-serif", 13).into_font().color(&red),
                )
        }))?
        .label("script stored a sensor")
        .legend(move |(x, y)| Circle::new((x + 10, y), 5, ShapeStyle::from(&red).filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_extremes() {
        let points: Vec<(f32, f32)> = (0..100_000)
            .map(|i| (i as f32, ((i % 1000) as f32 - 500.0).abs()))
            .collect();
        let out = decimate(&points, 100);
        assert!(out.len() <= 200);
        let max = out.iter().map(|p| p.1).fold(0.0, f64::max);
        let min = out.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!(max, 500.0);
        assert_eq!(min, 0.0);
    }

    #[test]
    fn renders_an_svg_with_marks() {
        let mut trace = Trace::default();
        for i in 0..100 {
            trace
                .points
                .push((i as f32 * 4.0, (i as f32 * 0.5).min(20.0)));
        }
        trace.actions.push(Action {
            time: 120.0,
            depth: 15.2,
            label: "sci_ruhp_behs=128".to_string(),
        });
        let svg = render_svg(&trace, "test", 40.0).expect("svg");
        assert!(svg.starts_with("<svg"), "{}", &svg[..40.min(svg.len())]);
        assert!(svg.contains("sci_ruhp_behs=128"));
        assert!(svg.contains("depth (m)"));
        assert!(svg.contains("<circle"));
    }
}
