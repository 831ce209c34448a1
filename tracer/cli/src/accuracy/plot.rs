//! The SVG plot of error against time, with the Pareto front marked.

use super::experiment::{Knob, Row, SceneReport};
use super::report::{short, sig3};
use std::fmt::Write as _;

impl SceneReport {
    /// Error (RMSE, log scale) against median time (log scale) as SVG: the one-knob
    /// settings against the reference on the left, antialiasing against the fine
    /// reference on the right, the Pareto front as a dashed staircase.
    pub fn to_svg(&self) -> String {
        let (pw, ph) = (460.0, 400.0);
        let mut s = String::new();
        let _ = writeln!(
            s,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" \
             font-family=\"sans-serif\" font-size=\"11\">",
            2.0 * pw,
            ph + 30.0
        );
        let _ = writeln!(
            s,
            "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{}\" y=\"18\" \
             text-anchor=\"middle\" font-size=\"14\">{}: RMSE against median {} time \
             ({}x{} px)</text>",
            pw,
            xml(&self.name),
            self.clock.name(),
            self.width,
            self.height
        );
        for (k, fine) in [false, true].into_iter().enumerate() {
            let rows: Vec<&Row> = self.rows.iter().filter(|r| r.case.fine == fine).collect();
            let title = if fine {
                format!("antialiasing vs {0}x{0} reference", self.options.fine_aa)
            } else {
                format!(
                    "one knob changed vs reference (f64, depth {}, {}x{})",
                    self.options.ref_depth, self.options.ref_aa, self.options.ref_aa
                )
            };
            let axis = format!("median {} time, ms (log)", self.clock.name());
            plot_panel(&mut s, (k as f64 * pw, 30.0, pw, ph), &title, &axis, &rows);
        }
        s.push_str("</svg>\n");
        s
    }
}

fn xml(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Log-scale ticks covering `[lo, hi]`: 1, 2, 5 times powers of ten.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let ticks = |ms: &[f64]| {
        let mut t = Vec::new();
        let mut e = lo.log10().floor() as i32 - 1;
        while 10f64.powi(e) <= hi * 1.0001 {
            for m in ms {
                let v = m * 10f64.powi(e);
                if v >= lo * 0.9999 && v <= hi * 1.0001 {
                    t.push(v);
                }
            }
            e += 1;
        }
        t
    };
    let t = ticks(&[1.0, 2.0, 5.0]);
    if t.len() >= 4 {
        t
    } else {
        ticks(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

fn plot_panel(s: &mut String, frame: (f64, f64, f64, f64), title: &str, axis: &str, rows: &[&Row]) {
    let (x0, y0, w, h) = frame;
    let (ml, mr, mt, mb) = (62.0, 14.0, 24.0, 40.0);
    let (left, right, top, bottom) = (x0 + ml, x0 + w - mr, y0 + mt, y0 + h - mb);
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"12\">{}</text>",
        (left + right) / 2.0,
        y0 + 14.0,
        xml(title)
    );
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>",
        right - left,
        bottom - top
    );
    if rows.is_empty() {
        return;
    }
    let times: Vec<f64> = rows.iter().map(|r| r.median_ms().max(1e-6)).collect();
    let errs: Vec<f64> = rows.iter().map(|r| r.metrics.rmse).collect();
    let (tmin, tmax) = times
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &t| (a.min(t), b.max(t)));
    let (tlo, thi) = (tmin / 1.25, tmax * 1.25);
    let pos: Vec<f64> = errs.iter().copied().filter(|&e| e > 0.0).collect();
    let emin = pos.iter().copied().fold(f64::INFINITY, f64::min);
    let emax = pos.iter().copied().fold(0.0f64, f64::max);
    let (elo, ehi) = if pos.is_empty() {
        (1e-6, 1.0)
    } else if emax / emin < 10.0 {
        let mid = (emin * emax).sqrt();
        (mid / 10.0, mid * 30.0)
    } else {
        // Room above the highest point for the legend.
        (emin / 2.0, emax * 8.0)
    };
    let fx = |t: f64| left + (t / tlo).log10() / (thi / tlo).log10() * (right - left);
    let fy = |e: f64| {
        if e <= 0.0 {
            bottom
        } else {
            bottom - (e / elo).log10() / (ehi / elo).log10() * (bottom - top)
        }
    };
    for t in log_ticks(tlo, thi) {
        let x = fx(t);
        let _ = writeln!(
            s,
            "<line x1=\"{x:.1}\" y1=\"{top}\" x2=\"{x:.1}\" y2=\"{bottom}\" stroke=\"#ddd\"/>\
             <text x=\"{x:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            bottom + 13.0,
            short(t)
        );
    }
    for e in log_ticks(elo, ehi) {
        let y = fy(e);
        let _ = writeln!(
            s,
            "<line x1=\"{left}\" y1=\"{y:.1}\" x2=\"{right}\" y2=\"{y:.1}\" stroke=\"#ddd\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
            left - 4.0,
            y + 4.0,
            short(e)
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
         <text x=\"{}\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 {} {})\">RMSE (log; 0 on the axis)</text>",
        (left + right) / 2.0,
        bottom + 30.0,
        xml(axis),
        x0 + 14.0,
        (top + bottom) / 2.0,
        x0 + 14.0,
        (top + bottom) / 2.0
    );
    // Pareto staircase through the front, fastest first.
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .zip(times.iter().zip(&errs))
        .filter(|(r, _)| r.pareto)
        .map(|(_, (&t, &e))| (t, e))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    if !front.is_empty() {
        let mut d = format!("M{:.1},{:.1}", fx(front[0].0), fy(front[0].1));
        for w2 in front.windows(2) {
            let _ = write!(d, " H{:.1} V{:.1}", fx(w2[1].0), fy(w2[1].1));
        }
        let _ = writeln!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"#000\" stroke-dasharray=\"5,3\"/>"
        );
    }
    for (r, (&t, &e)) in rows.iter().zip(times.iter().zip(&errs)) {
        let (x, y) = (fx(t), fy(e));
        let colour = r.case.knob.colour();
        if r.pareto {
            let _ = writeln!(
                s,
                "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"6\" fill=\"none\" stroke=\"#000\"/>"
            );
        }
        let _ = writeln!(
            s,
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"3.2\" fill=\"{colour}\"><title>{}: {} ms, RMSE {}</title></circle>\
             <text x=\"{:.1}\" y=\"{:.1}\" font-size=\"8\" fill=\"{colour}\">{}</text>",
            xml(&r.case.label),
            sig3(t),
            sig3(e),
            x + 5.0,
            y - 4.0,
            xml(&r.case.label)
        );
    }
    // Legend.
    let mut knobs: Vec<Knob> = Vec::new();
    for r in rows {
        if !knobs.contains(&r.case.knob) {
            knobs.push(r.case.knob);
        }
    }
    for (i, k) in knobs.iter().enumerate() {
        let y = top + 12.0 + 13.0 * i as f64;
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3.2\" fill=\"{}\"/><text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
            right - 90.0,
            y - 3.5,
            k.colour(),
            right - 83.0,
            y,
            k.name()
        );
    }
    let y = top + 12.0 + 13.0 * knobs.len() as f64;
    let _ = writeln!(
        s,
        "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"6\" fill=\"none\" stroke=\"#000\"/><text x=\"{:.1}\" y=\"{:.1}\">Pareto front</text>",
        right - 90.0,
        y - 3.5,
        right - 83.0,
        y
    );
}
