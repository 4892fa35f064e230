//! A minimal SVG scatter/line plot writer (log or linear axes, legend): enough for the reports,
//! no dependency.

use std::fmt::Write;

/// One series.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (x, y); non-finite or non-positive (on log axes) points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw lines between consecutive points.
    pub line: bool,
    /// Optional text beside each point (same order as `points`).
    pub labels: Vec<String>,
}

impl Series {
    /// A line series without point labels.
    pub fn line(label: String, points: Vec<(f64, f64)>) -> Series {
        Series { label, points, line: true, labels: Vec::new() }
    }
}

/// A plot.
pub struct Plot {
    /// Title.
    pub title: String,
    /// X axis label.
    pub xlabel: String,
    /// Y axis label.
    pub ylabel: String,
    /// Log-scale x.
    pub xlog: bool,
    /// Log-scale y.
    pub ylog: bool,
    /// Data.
    pub series: Vec<Series>,
    /// Optional horizontal reference line (y value, label).
    pub hline: Option<(f64, String)>,
}

const COLORS: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
    "#17becf",
];

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

impl Plot {
    /// Renders the plot as a standalone SVG document.
    pub fn render(&self) -> String {
        let (w, h) = (760.0, 440.0);
        let (l, r, t, b) = (80.0, 220.0, 40.0, 60.0);
        let tx = |x: f64| if self.xlog { x.log10() } else { x };
        let ty = |y: f64| if self.ylog { y.log10() } else { y };
        let ok = |x: f64, log: bool| x.is_finite() && (!log || x > 0.0);
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&(x, y)| ok(x, self.xlog) && ok(y, self.ylog))
            .map(|(x, y)| (tx(x), ty(y)))
            .chain(self.hline.iter().filter(|(y, _)| ok(*y, self.ylog)).map(|(y, _)| (f64::NAN, ty(*y))))
            .collect();
        let fold = |f: fn(f64, f64) -> f64, init: f64, sel: fn(&(f64, f64)) -> f64| {
            pts.iter().map(sel).filter(|v| v.is_finite()).fold(init, f)
        };
        let (mut x0, mut x1) =
            (fold(f64::min, f64::INFINITY, |p| p.0), fold(f64::max, f64::NEG_INFINITY, |p| p.0));
        let (mut y0, mut y1) =
            (fold(f64::min, f64::INFINITY, |p| p.1), fold(f64::max, f64::NEG_INFINITY, |p| p.1));
        if !x0.is_finite() {
            (x0, x1) = (0.0, 1.0);
        }
        if !y0.is_finite() {
            (y0, y1) = (0.0, 1.0);
        }
        let pad = |a: f64, b: f64| {
            let d = if b > a { (b - a) * 0.08 } else { 0.5 };
            (a - d, b + d)
        };
        let (x0, x1) = pad(x0, x1);
        let (y0, y1) = pad(y0, y1);
        let px = |x: f64| l + (x - x0) / (x1 - x0) * (w - l - r);
        let py = |y: f64| h - b - (y - y0) / (y1 - y0) * (h - t - b);
        let mut s = String::new();
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12"><rect width="100%" height="100%" fill="white"/><text x="{}" y="22" font-size="15" text-anchor="middle">{}</text>"#,
            (w - r + l) / 2.0,
            esc(&self.title)
        );
        let _ = write!(
            s,
            r#"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="black"/>"#,
            w - l - r,
            h - t - b
        );
        let ticks = |a: f64, b: f64, log: bool| -> Vec<f64> {
            if log {
                let (lo, hi) = (a.floor() as i64, b.ceil() as i64);
                let step = ((hi - lo) / 8).max(1);
                let mut v: Vec<f64> = Vec::new();
                for k in (lo..=hi).step_by(step as usize) {
                    v.push(k as f64);
                    if hi - lo <= 2 {
                        v.push(k as f64 + 2f64.log10());
                        v.push(k as f64 + 5f64.log10());
                    }
                }
                v.retain(|&t| t >= a && t <= b);
                v
            } else {
                let span = b - a;
                let mag = 10f64.powf(span.log10().floor());
                let step = [1.0, 2.0, 5.0, 10.0]
                    .iter()
                    .map(|m| m * mag)
                    .find(|st| span / st <= 8.0)
                    .unwrap_or(mag * 10.0);
                let mut v = (a / step).ceil() * step;
                let mut out = Vec::new();
                while v <= b {
                    out.push(v);
                    v += step;
                }
                out
            }
        };
        let fmt = |v: f64, log: bool| {
            if log {
                let m = 10f64.powf(v - v.floor()).round();
                if m == 1.0 {
                    format!("1e{}", v.floor() as i64)
                } else {
                    format!("{m}e{}", v.floor() as i64)
                }
            } else {
                format!("{v}")
            }
        };
        for xt in ticks(x0, x1, self.xlog) {
            let _ = write!(
                s,
                r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#ddd"/><text x="{0}" y="{3}" text-anchor="middle">{4}</text>"##,
                px(xt),
                t,
                h - b,
                h - b + 16.0,
                fmt(xt, self.xlog)
            );
        }
        for yt in ticks(y0, y1, self.ylog) {
            let _ = write!(
                s,
                r##"<line x1="{0}" y1="{1}" x2="{2}" y2="{1}" stroke="#ddd"/><text x="{3}" y="{4}" text-anchor="end">{5}</text>"##,
                l,
                py(yt),
                w - r,
                l - 6.0,
                py(yt) + 4.0,
                fmt(yt, self.ylog)
            );
        }
        let _ = write!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text><text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">{}</text>"#,
            (w - r + l) / 2.0,
            h - 18.0,
            esc(&self.xlabel),
            (h - b + t) / 2.0,
            (h - b + t) / 2.0,
            esc(&self.ylabel)
        );
        if let Some((y, label)) = &self.hline {
            if ok(*y, self.ylog) {
                let yy = py(ty(*y));
                let _ = write!(
                    s,
                    r##"<line x1="{l}" y1="{yy}" x2="{}" y2="{yy}" stroke="#444" stroke-dasharray="6 4"/><text x="{}" y="{}" font-size="11">{}</text>"##,
                    w - r,
                    l + 4.0,
                    yy - 4.0,
                    esc(label)
                );
            }
        }
        for (i, se) in self.series.iter().enumerate() {
            let c = COLORS[i % COLORS.len()];
            let kept: Vec<usize> = (0..se.points.len())
                .filter(|&k| ok(se.points[k].0, self.xlog) && ok(se.points[k].1, self.ylog))
                .collect();
            let p: Vec<(f64, f64)> =
                kept.iter().map(|&k| (px(tx(se.points[k].0)), py(ty(se.points[k].1)))).collect();
            for (j, &k) in kept.iter().enumerate() {
                if let Some(lbl) = se.labels.get(k) {
                    let _ = write!(
                        s,
                        r#"<text x="{:.1}" y="{:.1}" font-size="10" fill="{c}">{}</text>"#,
                        p[j].0 + 5.0,
                        p[j].1 - 5.0,
                        esc(lbl)
                    );
                }
            }
            if se.line && p.len() > 1 {
                let d: Vec<String> = p.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
                let _ = write!(
                    s,
                    r#"<polyline fill="none" stroke="{c}" stroke-width="1.5" points="{}"/>"#,
                    d.join(" ")
                );
            }
            for (x, y) in &p {
                let _ = write!(s, r#"<circle cx="{x:.1}" cy="{y:.1}" r="3.5" fill="{c}"/>"#);
            }
            let ly = t + 14.0 + 18.0 * i as f64;
            let _ = write!(
                s,
                r#"<circle cx="{}" cy="{}" r="4" fill="{c}"/><text x="{}" y="{}">{}</text>"#,
                w - r + 16.0,
                ly - 4.0,
                w - r + 26.0,
                ly,
                esc(&se.label)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}
