//! The sign-convention picture, drawn by hand as SVG: shown inline in every FMU's
//! `documentation/index.html` (a longitudinal scene's page without the planar top view) and
//! checked in as `docs/sign-convention.svg` (the drift test in `tests/docs_reference.rs` keeps
//! the two equal).

/// The picture: a side view of the body on the vibrating support with the forces and the
/// positive directions, and a top view with the vibration direction `angle`.
pub const SIGN_CONVENTION_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="900" height="370" viewBox="0 0 900 370" font-family="sans-serif" font-size="13">
<title>vibrofric sign convention</title>
<defs>
<marker id="ah" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="8" markerHeight="8" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="context-stroke"/></marker>
<pattern id="hatch" width="8" height="8" patternUnits="userSpaceOnUse" patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="8" stroke="#777" stroke-width="2"/></pattern>
</defs>
<rect x="0" y="0" width="900" height="370" fill="#ffffff"/>
<text x="20" y="24" font-size="15" font-weight="bold">Side view (x along the sliding direction)</text>
<!-- axes -->
<line x1="40" y1="52" x2="100" y2="52" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="106" y="56">x</text>
<circle cx="40" cy="52" r="6" fill="none" stroke="#000"/>
<circle cx="40" cy="52" r="1.8" fill="#000"/>
<text x="22" y="76">y: out of the page</text>
<!-- normal force -->
<line x1="250" y1="62" x2="250" y2="117" stroke="#333" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="258" y="80">F_N (normal force)</text>
<!-- body velocity -->
<line x1="158" y1="108" x2="225" y2="108" stroke="#333" stroke-width="2" marker-end="url(#ah)"/>
<text x="150" y="98">v = (v_x, v_y)</text>
<!-- body -->
<rect x="150" y="120" width="200" height="70" fill="#e8eef6" stroke="#333" stroke-width="1.5"/>
<text x="224" y="160" font-size="15">body m</text>
<!-- drive -->
<line x1="352" y1="148" x2="420" y2="148" stroke="#2ca02c" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="426" y="144" fill="#2ca02c">drive along +x:</text>
<text x="426" y="160" fill="#2ca02c">F_d, v_d, or spring k_d, c_d</text>
<!-- friction on the body -->
<line x1="150" y1="182" x2="84" y2="182" stroke="#d62728" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="40" y="187" fill="#d62728">−F_F</text>
<!-- contact zone: bristles -->
<g stroke="#555" stroke-width="1.5" fill="none">
<path d="M175,222 l5,-6 l-10,-7 l10,-7 l-10,-7 l5,-5"/>
<path d="M225,222 l5,-6 l-10,-7 l10,-7 l-10,-7 l5,-5"/>
<path d="M275,222 l5,-6 l-10,-7 l10,-7 l-10,-7 l5,-5"/>
<path d="M325,222 l5,-6 l-10,-7 l10,-7 l-10,-7 l5,-5"/>
</g>
<text x="362" y="198">contact zone: deformation s,</text>
<text x="362" y="214">F_F = k_t·s (LuGre: + damping)</text>
<!-- support -->
<rect x="40" y="222" width="420" height="34" fill="url(#hatch)" stroke="#333"/>
<line x1="395" y1="272" x2="455" y2="272" stroke="#1f77b4" stroke-width="2.5" marker-start="url(#ah)" marker-end="url(#ah)"/>
<text x="462" y="277" fill="#1f77b4">v_s</text>
<text x="40" y="278">support: u = u0·sin(2π·f·t + phase), v_s = du/dt</text>
<text x="40" y="296">(plus v_sx, v_sy from the importer with input support motion)</text>
<text x="20" y="332">v_r = v − v_s. F_F resists v_r: while the body slides towards +x relative to the support,</text>
<text x="20" y="350">F_Fx &gt; 0 and the support pushes the body with −F_F (red).</text>
<!-- top view -->
<text x="630" y="24" font-size="15" font-weight="bold">Top view (planar scenes)</text>
<line x1="660" y1="210" x2="860" y2="210" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="866" y="214">x</text>
<line x1="660" y1="210" x2="660" y2="60" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="666" y="66">y</text>
<line x1="660" y1="210" x2="772" y2="115" stroke="#1f77b4" stroke-width="2.5" marker-start="url(#ah)" marker-end="url(#ah)"/>
<path d="M720,210 A60,60 0 0,0 706,171" fill="none" stroke="#1f77b4" stroke-width="1.5"/>
<text x="726" y="196" fill="#1f77b4">angle</text>
<text x="778" y="110" fill="#1f77b4">u</text>
<text x="630" y="240">angle = 0: longitudinal (along the drive)</text>
<text x="630" y="258">angle = π/2: transverse</text>
<text x="630" y="276">F_F = (F_Fx, F_Fy), s = (s_x, s_y)</text>
</svg>
"##;

/// The picture for a scene's page: the whole of [`SIGN_CONVENTION_SVG`] for a planar scene; for
/// a longitudinal one, the side view alone (no top view, no `y`), on a narrower canvas.
pub fn sign_convention_svg(planar: bool) -> String {
    if planar {
        return SIGN_CONVENTION_SVG.to_string();
    }
    let side = SIGN_CONVENTION_SVG
        .split("<!-- top view -->")
        .next()
        .unwrap_or(SIGN_CONVENTION_SVG);
    let side = side
        .replace(
            r#"width="900" height="370" viewBox="0 0 900 370""#,
            r#"width="640" height="370" viewBox="0 0 640 370""#,
        )
        .replace(
            r#"<rect x="0" y="0" width="900""#,
            r#"<rect x="0" y="0" width="640""#,
        )
        .replace("<text x=\"22\" y=\"76\">y: out of the page</text>\n", "")
        .replace("v = (v_x, v_y)", "v = v_x")
        .replace(
            "(plus v_sx, v_sy from the importer",
            "(plus v_sx from the importer",
        );
    format!("{side}</svg>\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn longitudinal_picture_has_no_top_view_and_stays_well_formed() {
        let planar = sign_convention_svg(true);
        assert_eq!(planar, SIGN_CONVENTION_SVG);
        assert!(planar.contains("Top view (planar scenes)"));
        let l = sign_convention_svg(false);
        assert!(!l.contains("Top view") && !l.contains("angle") && !l.contains("v_sy"));
        assert!(!l.contains("y: out of the page") && l.contains("v = v_x"));
        assert!(l.contains("Side view") && l.contains("viewBox=\"0 0 640 370\""));
        assert!(l.trim_end().ends_with("</svg>"));
        assert_eq!(l.matches("<svg").count(), 1);
        assert_eq!(l.matches("</svg>").count(), 1);
    }
}
