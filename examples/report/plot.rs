//! Work–precision plots: error against CPU time on log–log axes, one SVG per case with two
//! panels (`F_mean` relative error, and the maximum `F_Fx` error over the samples / F_C) and the
//! legend beside them, outside the axes; and a PNG of the same drawing beside each SVG, for
//! viewers without SVG support (rasterized by resvg with the system's fonts).
//!
//! Every solver keeps one colour and one marker in every plot ([`style`]), chosen so that no
//! two solvers share either (DOP853 in Rust and in scipy: blue filled diamonds against red
//! downward triangles).

use std::path::Path;

use plotters::prelude::*;

use super::Row;

/// Marker shapes; `open` draws the outline only.
#[derive(Clone, Copy)]
enum Shape {
    Circle,
    Square,
    TriangleUp,
    TriangleDown,
    Diamond,
    Cross,
    Plus,
}

#[derive(Clone, Copy)]
struct Style {
    colour: RGBColor,
    shape: Shape,
    open: bool,
}

/// The style of a series, by its label (solver, and communication step for the FMU).
fn style(label: &str) -> Style {
    let s = |r, g, b, shape, open| Style {
        colour: RGBColor(r, g, b),
        shape,
        open,
    };
    match label {
        "vibrofric" => s(0, 0, 0, Shape::Circle, false),
        "vibrofric-1step" => s(110, 110, 110, Shape::Circle, true),
        "diffsol BDF" => s(44, 160, 44, Shape::Square, false),
        "diffsol TR-BDF2" => s(120, 130, 20, Shape::Square, true),
        "diffsol ESDIRK34" => s(23, 170, 190, Shape::TriangleUp, false),
        "differential-equations DOP853" => s(31, 119, 180, Shape::Diamond, false),
        "differential-equations Radau5" => s(148, 103, 189, Shape::Diamond, true),
        "scipy-DOP853" => s(214, 39, 40, Shape::TriangleDown, false),
        "scipy-LSODA" => s(140, 86, 75, Shape::Cross, false),
        "scipy-Radau" => s(227, 119, 194, Shape::TriangleUp, true),
        l if l.starts_with("fmu-fmpy") && l.contains("h=1e-3") => {
            s(255, 127, 14, Shape::Plus, false)
        }
        l if l.starts_with("fmu-fmpy") => s(190, 140, 0, Shape::TriangleDown, true),
        _ => s(60, 60, 60, Shape::Square, true),
    }
}

/// One marker at a point (in the backend's pixel coordinates relative to the point).
fn marker<'a, C: Copy + 'a, DB: DrawingBackend + 'a>(
    at: C,
    st: Style,
    size: i32,
) -> DynElement<'a, DB, C> {
    let c = st.colour;
    let fill = if st.open {
        c.stroke_width(2)
    } else {
        c.filled()
    };
    let line = c.stroke_width(2);
    let r = size;
    let poly = |pts: Vec<(i32, i32)>| -> DynElement<'a, DB, C> {
        if st.open {
            let mut closed = pts.clone();
            closed.push(pts[0]);
            (EmptyElement::at(at) + PathElement::new(closed, line)).into_dyn()
        } else {
            (EmptyElement::at(at) + Polygon::new(pts, fill)).into_dyn()
        }
    };
    match st.shape {
        Shape::Circle => (EmptyElement::at(at) + Circle::new((0, 0), r, fill)).into_dyn(),
        Shape::Square => poly(vec![(-r, -r), (r, -r), (r, r), (-r, r)]),
        Shape::TriangleUp => poly(vec![(0, -r - 1), (r + 1, r), (-r - 1, r)]),
        Shape::TriangleDown => poly(vec![(0, r + 1), (r + 1, -r), (-r - 1, -r)]),
        Shape::Diamond => poly(vec![(0, -r - 2), (r + 1, 0), (0, r + 2), (-r - 1, 0)]),
        Shape::Cross => (EmptyElement::at(at)
            + PathElement::new(vec![(-r, -r), (r, r)], line)
            + PathElement::new(vec![(-r, r), (r, -r)], line))
        .into_dyn(),
        Shape::Plus => (EmptyElement::at(at)
            + PathElement::new(vec![(-r - 1, 0), (r + 1, 0)], line)
            + PathElement::new(vec![(0, -r - 1), (0, r + 1)], line))
        .into_dyn(),
    }
}

fn label(r: &Row) -> String {
    match r.comm_step {
        Some(h) if r.solver.starts_with("fmu") => format!("{} h={h:e}", r.solver),
        _ => r.solver.clone(),
    }
}

/// Series labels in legend order: vibrofric first, then the peers by name.
fn labels(rows: &[&Row]) -> Vec<String> {
    let mut names: Vec<String> = rows.iter().filter(|r| r.ok()).map(|r| label(r)).collect();
    names.sort_by_key(|n| (!n.starts_with("vibrofric"), n.clone()));
    names.dedup();
    names
}

/// One series per label, ordered by tolerance: (run time, error) points.
fn series(rows: &[&Row], name: &str, err: fn(&Row) -> f64) -> Vec<(f64, f64)> {
    let mut pts: Vec<(f64, f64, f64)> = rows
        .iter()
        .filter(|r| label(r) == name && r.ok())
        .map(|r| (r.tol, r.cpu_s, err(r)))
        .filter(|(_, t, e)| t.is_finite() && *t > 0.0 && e.is_finite())
        .collect();
    pts.sort_by(|a, b| b.0.total_cmp(&a.0));
    pts.into_iter().map(|(_, t, e)| (t, e.max(1e-16))).collect()
}

const FONT: &str = "sans-serif";

/// Writes the plot for one case: `<path>` (SVG) and the same drawing as PNG beside it.
pub fn work_precision(path: &Path, case: &str, rows: &[&Row]) {
    {
        let root = SVGBackend::new(path, (1500, 640)).into_drawing_area();
        root.fill(&WHITE).unwrap();
        let (plots, legend) = root.split_horizontally(1170);
        let title = plots.titled(
            &format!("{case}: error against run time (lower left is better)"),
            (FONT, 24),
        );
        let title = title.unwrap();
        let panels = title.split_evenly((1, 2));
        type Measure = (&'static str, fn(&Row) -> f64);
        let measures: [Measure; 2] = [
            ("F_mean relative error", |r| r.f_mean_rel_err),
            ("max |F_Fx error| / F_C", |r| r.max_ffx_err),
        ];
        let names = labels(rows);
        for (panel, (what, err)) in panels.iter().zip(measures) {
            let all: Vec<(String, Vec<(f64, f64)>)> = names
                .iter()
                .map(|n| (n.clone(), series(rows, n, err)))
                .filter(|(_, p)| !p.is_empty())
                .collect();
            let (mut t0, mut t1, mut e0, mut e1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
            for &(t, e) in all.iter().flat_map(|(_, p)| p.iter()) {
                t0 = t0.min(t);
                t1 = t1.max(t);
                e0 = e0.min(e);
                e1 = e1.max(e);
            }
            if !(t0 < t1 && e0 <= e1) {
                continue;
            }
            let mut chart = ChartBuilder::on(panel)
                .caption(what, (FONT, 20))
                .margin(14)
                .x_label_area_size(52)
                .y_label_area_size(84)
                .build_cartesian_2d(
                    (t0 / 1.5..t1 * 1.5).log_scale(),
                    (e0 / 3.0..(e1 * 3.0).max(e0 * 10.0)).log_scale(),
                )
                .unwrap();
            chart
                .configure_mesh()
                .x_desc("run time [s]")
                .y_desc(what)
                .axis_desc_style((FONT, 18))
                .label_style((FONT, 15))
                .x_label_formatter(&|v| format!("{v:.0e}"))
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .draw()
                .unwrap();
            for (name, p) in &all {
                let st = style(name);
                chart
                    .draw_series(LineSeries::new(p.clone(), st.colour.stroke_width(2)))
                    .unwrap();
                let area = chart.plotting_area();
                for &q in p {
                    area.draw(&marker(q, st, 5)).unwrap();
                }
            }
        }
        // The legend, outside the axes.
        legend
            .draw(&Text::new(
                "solver",
                (16, 70),
                (FONT, 19).into_font().color(&BLACK),
            ))
            .unwrap();
        for (i, name) in names.iter().enumerate() {
            let st = style(name);
            let y = 110 + 34 * i as i32;
            legend
                .draw(&PathElement::new(
                    vec![(16, y), (56, y)],
                    st.colour.stroke_width(2),
                ))
                .unwrap();
            legend.draw(&marker((36, y), st, 6)).unwrap();
            legend
                .draw(&Text::new(
                    name.clone(),
                    (66, y - 9),
                    (FONT, 16).into_font().color(&BLACK),
                ))
                .unwrap();
        }
        root.present().unwrap();
    }
    if let Err(e) = png_beside(path) {
        eprintln!("{}: no PNG: {e}", path.display());
    }
}

/// Rasterizes the SVG at `svg` to the same name with `.png`, with the system's fonts (the
/// generic `sans-serif` mapped to the first of DejaVu Sans, Liberation Sans, Noto Sans, Arial
/// that is installed).
fn png_beside(svg: &Path) -> Result<(), String> {
    use resvg::{tiny_skia, usvg};
    let data = std::fs::read(svg).map_err(|e| e.to_string())?;
    let mut opt = usvg::Options::default();
    let family = {
        let db = opt.fontdb_mut();
        db.load_system_fonts();
        let family = ["DejaVu Sans", "Liberation Sans", "Noto Sans", "Arial"]
            .into_iter()
            .find(|f| {
                db.faces()
                    .any(|face| face.families.iter().any(|(n, _)| n == f))
            })
            .ok_or(
                "no sans-serif font installed (DejaVu Sans, Liberation Sans, Noto Sans or Arial)",
            )?;
        db.set_sans_serif_family(family);
        family
    };
    opt.font_family = family.to_string();
    let tree = usvg::Tree::from_data(&data, &opt).map_err(|e| e.to_string())?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or("empty picture")?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap
        .save_png(svg.with_extension("png"))
        .map_err(|e| e.to_string())
}
