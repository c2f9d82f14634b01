//! The sign-convention picture, drawn by hand as SVG: shown inline in every FMU's
//! `documentation/index.html` and checked in as `docs/sign-convention.svg` (the drift test in
//! `tests/docs_reference.rs` keeps the two equal).

/// The picture: a side view of the body on the vibrating support with the forces and the
/// positive directions, and a top view with the vibration direction `angle`.
pub const SIGN_CONVENTION_SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="760" height="330" viewBox="0 0 760 330" font-family="sans-serif" font-size="13">
<title>vibrofric sign convention</title>
<defs>
<marker id="ah" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="8" markerHeight="8" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="context-stroke"/></marker>
<pattern id="hatch" width="8" height="8" patternUnits="userSpaceOnUse" patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="8" stroke="#777" stroke-width="2"/></pattern>
</defs>
<rect x="0" y="0" width="760" height="330" fill="#ffffff"/>
<text x="20" y="24" font-size="15" font-weight="bold">Side view (x along the sliding direction)</text>
<!-- support -->
<rect x="40" y="215" width="420" height="34" fill="url(#hatch)" stroke="#333"/>
<text x="40" y="272">support: u = u0·sin(2π·f·t + phase), velocity v_s = du/dt</text>
<text x="40" y="290">(plus v_sx, v_sy set by the importer in scenes with input support motion)</text>
<line x1="395" y1="232" x2="455" y2="232" stroke="#1f77b4" stroke-width="2.5" marker-start="url(#ah)" marker-end="url(#ah)"/>
<text x="397" y="209" fill="#1f77b4">v_s</text>
<!-- contact zone: bristles -->
<g stroke="#555" stroke-width="1.5" fill="none">
<path d="M175,215 l5,-6 l-10,-6 l10,-6 l-10,-6 l5,-4"/>
<path d="M225,215 l5,-6 l-10,-6 l10,-6 l-10,-6 l5,-4"/>
<path d="M275,215 l5,-6 l-10,-6 l10,-6 l-10,-6 l5,-4"/>
<path d="M325,215 l5,-6 l-10,-6 l10,-6 l-10,-6 l5,-4"/>
</g>
<text x="345" y="200">contact zone: deformation s,</text>
<text x="345" y="186">F_F = k_t·s (+ LuGre damping)</text>
<!-- body -->
<rect x="150" y="115" width="200" height="72" fill="#e8eef6" stroke="#333" stroke-width="1.5"/>
<text x="228" y="156" font-size="15">body m</text>
<!-- normal force -->
<line x1="250" y1="62" x2="250" y2="112" stroke="#333" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="258" y="80">F_N (presses the body on the support)</text>
<!-- drive -->
<line x1="352" y1="140" x2="420" y2="140" stroke="#2ca02c" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="426" y="136" fill="#2ca02c">drive along +x: force F_d,</text>
<text x="426" y="152" fill="#2ca02c">velocity v_d, or spring k_d, c_d</text>
<!-- body velocity -->
<line x1="160" y1="104" x2="225" y2="104" stroke="#333" stroke-width="2" marker-end="url(#ah)"/>
<text x="160" y="97">v = (v_x, v_y)</text>
<!-- friction on the body -->
<line x1="150" y1="180" x2="84" y2="180" stroke="#d62728" stroke-width="2.5" marker-end="url(#ah)"/>
<text x="20" y="170" fill="#d62728">−F_F</text>
<!-- axes -->
<line x1="40" y1="60" x2="100" y2="60" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="104" y="64">x</text>
<circle cx="40" cy="60" r="6" fill="none" stroke="#000"/>
<circle cx="40" cy="60" r="1.8" fill="#000"/>
<text x="22" y="48">y (out of the page)</text>
<text x="20" y="316">v_r = v − v_s. F_F resists v_r: while the body slides towards +x relative to the support, F_Fx &gt; 0 and the support pushes the body with −F_F (red).</text>
<!-- top view -->
<text x="520" y="24" font-size="15" font-weight="bold">Top view (planar scenes)</text>
<line x1="560" y1="200" x2="720" y2="200" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="724" y="204">x</text>
<line x1="560" y1="200" x2="560" y2="50" stroke="#000" stroke-width="1.5" marker-end="url(#ah)"/>
<text x="566" y="56">y</text>
<line x1="560" y1="200" x2="672" y2="105" stroke="#1f77b4" stroke-width="2.5" marker-start="url(#ah)" marker-end="url(#ah)"/>
<path d="M620,200 A60,60 0 0,0 606,161" fill="none" stroke="#1f77b4" stroke-width="1.5"/>
<text x="626" y="186" fill="#1f77b4">angle</text>
<text x="678" y="100" fill="#1f77b4">u</text>
<text x="520" y="226">angle = 0: longitudinal (along the drive)</text>
<text x="520" y="244">angle = π/2: transverse</text>
<text x="520" y="262">F_F = (F_Fx, F_Fy), s = (s_x, s_y)</text>
</svg>
"##;
