//! Work–precision plots: error against CPU time on log–log axes, one SVG per case with two
//! panels (`F_mean` relative error, and the maximum `F_Fx` error over the samples / F_C).

use std::path::Path;

use plotters::prelude::*;

use super::Row;

/// Colours by solver: vibrofric in black, peers in distinct hues.
fn colour(i: usize) -> RGBColor {
    const PALETTE: [RGBColor; 14] = [
        RGBColor(0, 0, 0),
        RGBColor(120, 120, 120),
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
        RGBColor(188, 189, 34),
        RGBColor(255, 187, 120),
        RGBColor(152, 223, 138),
        RGBColor(174, 199, 232),
    ];
    PALETTE[i % PALETTE.len()]
}

/// One series per solver (and communication step, for the FMU), ordered by tolerance.
fn series(rows: &[&Row], err: fn(&Row) -> f64) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut names: Vec<String> = rows.iter().map(|r| label(r)).collect();
    names.sort_by_key(|n| (!n.starts_with("vibrofric"), n.clone()));
    names.dedup();
    names
        .into_iter()
        .map(|name| {
            let mut pts: Vec<(f64, f64, f64)> = rows
                .iter()
                .filter(|r| label(r) == name && r.ok())
                .map(|r| (r.tol, r.cpu_s, err(r)))
                .filter(|(_, t, e)| t.is_finite() && *t > 0.0 && e.is_finite())
                .collect();
            pts.sort_by(|a, b| b.0.total_cmp(&a.0));
            (name, pts.into_iter().map(|(_, t, e)| (t, e)).collect())
        })
        .filter(|(_, pts): &(String, Vec<(f64, f64)>)| !pts.is_empty())
        .collect()
}

fn label(r: &Row) -> String {
    match r.comm_step {
        Some(h) if r.solver.starts_with("fmu") => format!("{} h={h:e}", r.solver),
        _ => r.solver.clone(),
    }
}

/// Writes the plot for one case.
pub fn work_precision(path: &Path, case: &str, rows: &[&Row]) {
    let root = SVGBackend::new(path, (1300, 560)).into_drawing_area();
    root.fill(&WHITE).unwrap();
    let panels = root.split_evenly((1, 2));
    type Measure = (&'static str, fn(&Row) -> f64);
    let measures: [Measure; 2] = [
        ("F_mean relative error", |r| r.f_mean_rel_err),
        ("max |F_Fx error| / F_C", |r| r.max_ffx_err),
    ];
    // One colour per solver in both panels.
    let mut names: Vec<String> = rows.iter().map(|r| label(r)).collect();
    names.sort_by_key(|n| (!n.starts_with("vibrofric"), n.clone()));
    names.dedup();
    for (panel, (what, err)) in panels.iter().zip(measures) {
        let s = series(rows, err);
        let pts = s.iter().flat_map(|(_, p)| p.iter());
        let (mut t0, mut t1, mut e0, mut e1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
        for &(t, e) in pts {
            t0 = t0.min(t);
            t1 = t1.max(t);
            let e = e.max(1e-16);
            e0 = e0.min(e);
            e1 = e1.max(e);
        }
        if !(t0 < t1 && e0 <= e1) {
            continue;
        }
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{case}: {what}"), ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (t0 / 1.5..t1 * 1.5).log_scale(),
                (e0 / 3.0..(e1 * 3.0).max(e0 * 10.0)).log_scale(),
            )
            .unwrap();
        chart
            .configure_mesh()
            .x_desc("run time [s]")
            .y_desc(what)
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .unwrap();
        for (name, p) in &s {
            let c = colour(names.iter().position(|n| n == name).unwrap_or(0));
            let p: Vec<(f64, f64)> = p.iter().map(|&(t, e)| (t, e.max(1e-16))).collect();
            chart
                .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
                .unwrap()
                .label(name.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c));
            chart
                .draw_series(p.iter().map(|&q| Circle::new(q, 3, c.filled())))
                .unwrap();
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .unwrap();
    }
    root.present().unwrap();
}
