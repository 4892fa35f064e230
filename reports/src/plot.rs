//! Log-log plots as SVG (plotters' SVG backend: no system dependency, no font files; text is
//! left to the SVG viewer). Every series is in the legend; nothing is labelled in place, so
//! labels cannot overlap.

use plotters::prelude::*;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mark {
    /// A polyline with small dots at the points.
    Line,
    /// Filled circles.
    Circle,
    /// Filled triangles.
    Triangle,
    /// Hollow circles.
    Ring,
    /// Crosses.
    Cross,
}

/// One series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// (x, y) points; non-positive or non-finite values are left out (log axes).
    pub points: Vec<(f64, f64)>,
    /// Marker.
    pub mark: Mark,
    /// Colour index (series sharing an index share a colour).
    pub colour: usize,
    /// Vertical segments joining pairs of points at the same x (e.g. median to max).
    pub whiskers: Vec<(f64, f64, f64)>,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, colour: usize, points: Vec<(f64, f64)>) -> Series {
        Series { label: label.into(), points, mark: Mark::Line, colour, whiskers: Vec::new() }
    }
}

/// A plot.
#[derive(Clone, Debug)]
pub struct Plot {
    /// Caption.
    pub title: String,
    /// X axis label.
    pub xlabel: String,
    /// Y axis label.
    pub ylabel: String,
    /// Series.
    pub series: Vec<Series>,
    /// A dashed horizontal reference line and its legend text.
    pub hline: Option<(f64, String)>,
}

/// Tick text: plain decimals for 1e-3..1e4, else `1e7`-style powers.
fn tick(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let e = x.abs().log10();
    if (-3.0..4.0).contains(&e) {
        let s = format!("{x:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else if (e - e.round()).abs() < 1e-9 {
        format!("1e{}", e.round() as i32)
    } else {
        format!("{x:.0e}")
    }
}

/// A colour of a fixed, readable palette.
fn colour(i: usize) -> RGBColor {
    const P: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    P[i % P.len()]
}

/// The range of the positive finite values, widened to whole decades (log axis).
fn decades(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
    if hi == 0.0 {
        return (0.1, 10.0);
    }
    let (l, h) = (10f64.powf(lo.log10().floor()), 10f64.powf(hi.log10().ceil()));
    if l == h {
        (l / 10.0, h * 10.0)
    } else {
        (l, h)
    }
}

fn ok(x: f64, y: f64) -> bool {
    x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0
}

impl Plot {
    /// The plot as an SVG document.
    ///
    /// # Errors
    /// When plotters fails to draw (a message).
    pub fn render(&self) -> Result<String, String> {
        let mut svg = String::new();
        self.draw(&mut svg).map_err(|e| format!("plot {:?}: {e}", self.title))?;
        Ok(svg)
    }

    fn draw(&self, svg: &mut String) -> Result<(), Box<dyn std::error::Error + '_>> {
        let all = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let whisk = || self.series.iter().flat_map(|s| s.whiskers.iter().flat_map(|w| [w.1, w.2]));
        let (x0, x1) = decades(all().map(|p| p.0));
        let hl = self.hline.as_ref().map(|h| h.0);
        let (y0, y1) = decades(all().map(|p| p.1).chain(whisk()).chain(hl));
        let root = SVGBackend::with_string(svg, (960, 640)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(self.xlabel.as_str())
            .y_desc(self.ylabel.as_str())
            .x_label_formatter(&|x| tick(*x))
            .y_label_formatter(&|y| tick(*y))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.12))
            .draw()?;
        for s in &self.series {
            let c = colour(s.colour);
            let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(|&(x, y)| ok(x, y)).collect();
            for &(x, lo, hi) in &s.whiskers {
                if ok(x, lo) && ok(x, hi) {
                    chart.draw_series(LineSeries::new([(x, lo), (x, hi)], c.mix(0.6).stroke_width(1)))?;
                }
            }
            let anno = match s.mark {
                Mark::Line => {
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
                    chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?
                }
                Mark::Circle => chart.draw_series(pts.iter().map(|&p| Circle::new(p, 6, c.filled())))?,
                Mark::Ring => chart.draw_series(pts.iter().map(|&p| Circle::new(p, 6, c.stroke_width(2))))?,
                Mark::Triangle => {
                    chart.draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 7, c.filled())))?
                }
                Mark::Cross => chart.draw_series(pts.iter().map(|&p| Cross::new(p, 6, c.stroke_width(2))))?,
            };
            let mark = s.mark;
            anno.label(s.label.as_str()).legend(
                move |(x, y)| -> DynElement<'static, SVGBackend, (i32, i32)> {
                    match mark {
                        Mark::Line => {
                            PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)).into_dyn()
                        }
                        Mark::Circle => Circle::new((x + 9, y), 5, c.filled()).into_dyn(),
                        Mark::Ring => Circle::new((x + 9, y), 5, c.stroke_width(2)).into_dyn(),
                        Mark::Triangle => TriangleMarker::new((x + 9, y), 6, c.filled()).into_dyn(),
                        Mark::Cross => Cross::new((x + 9, y), 5, c.stroke_width(2)).into_dyn(),
                    }
                },
            );
        }
        if let Some((y, label)) = &self.hline {
            let dashes: Vec<(f64, f64)> =
                (0..=60).map(|i| x0 * (x1 / x0).powf(i as f64 / 60.0)).map(|x| (x, *y)).collect();
            chart
                .draw_series(
                    dashes.chunks(2).map(|w| PathElement::new(w.to_vec(), BLACK.mix(0.55).stroke_width(1))),
                )?
                .label(label.as_str())
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 7, y), (x + 11, y), (x + 18, y)], BLACK.mix(0.55))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
        root.present()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_read_as_numbers() {
        assert_eq!(tick(5.0), "5");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(1e7), "1e7");
        assert_eq!(tick(1e-6), "1e-6");
    }

    #[test]
    fn renders_every_series_in_the_legend() {
        let p = Plot {
            title: "t".into(),
            xlabel: "x".into(),
            ylabel: "y".into(),
            series: vec![
                Series::line("alpha", 0, vec![(1.0, 2.0), (10.0, 3.0)]),
                Series {
                    label: "beta".into(),
                    points: vec![(3.0, 0.5), (f64::NAN, 1.0), (0.0, 1.0)],
                    mark: Mark::Ring,
                    colour: 1,
                    whiskers: vec![(3.0, 0.5, 5.0)],
                },
            ],
            hline: Some((8.0, "target".into())),
        };
        let svg = p.render().unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        for l in ["alpha", "beta", "target", "\n1\n", "\n10\n"] {
            assert!(svg.contains(l), "{l} missing");
        }
        assert!(!svg.contains("NaN"));
    }
}
