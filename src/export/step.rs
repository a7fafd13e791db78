//! Writing the traced MAT as a STEP AP214 wireframe (`<stem>.mat.step`).
//!
//! ISO 10303-21 text, schema `AUTOMOTIVE_DESIGN` (AP214), millimetres. Each seam is one
//! `B_SPLINE_CURVE_WITH_KNOTS` named `'seam <id>'` (its [`SeamFit`]), each skeletal edge at a
//! vertex one straight `B_SPLINE_CURVE_WITH_KNOTS` of degree 1 named `'skeletal edge <id>'`
//! (from its first ball's centre to the vertex), each degenerate curve (a cylinder's axis) one
//! `B_SPLINE_CURVE_WITH_KNOTS` named `'degenerate curve <index>'` fitted through its centres,
//! each junction one `CARTESIAN_POINT` named `'junction <id>'`; they are
//! `GEOMETRIC_CURVE_SET`s (`'seams'`, `'skeletal edges'`, `'degenerate curves'`,
//! `'junctions'`) of one `GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION`, framed by the
//! product structure OCCT itself writes (`PRODUCT` … `SHAPE_DEFINITION_REPRESENTATION`, one
//! application context, the unit context of OCCT's files), so FreeCAD/OCCT import one edge per
//! seam, then one per skeletal edge, one per degenerate curve, and one vertex per junction.
//! The radius has no place in a wireframe: it is in the JSON report.
//!
//! Optionally the input part is included: its DATA section is copied verbatim, every `#n`
//! outside strings and comments renumbered past our ids, keeping its own product structure and
//! units, so one open shows the part and its MAT.
//!
//! truck-stepio cannot help here: it writes no wires or curve sets, and its solid writer emits a
//! schema other than AP214. The entities are simple enough to print directly.

use crate::error::{Error, Result};
use crate::fit::SeamFit;
use crate::medial::MedialAxis;
use std::fmt::Write as _;
use std::path::Path;

/// The uncertainty written into the representation context (mm), as OCCT writes it.
pub const UNCERTAINTY: f64 = 1e-7;

/// Writes `mat` (with `fits`: one per seam, and one per degenerate piece, `None` where it is
/// no curve) to `path` atomically: a temporary file in the same folder, renamed over `path`.
/// `name` names the product (the part's stem). With `solid`, the input STEP file whose
/// entities are copied in.
pub fn write_mat_step(
    path: &Path,
    name: &str,
    mat: &MedialAxis,
    fits: (&[SeamFit], &[Option<SeamFit>]),
    solid: Option<&Path>,
) -> Result<()> {
    let solid = match solid {
        Some(p) => {
            let bytes = std::fs::read(p).map_err(|source| Error::Io {
                path: p.to_path_buf(),
                source,
            })?;
            Some((p, String::from_utf8_lossy(&bytes).into_owned()))
        }
        None => None,
    };
    let text = mat_step_text(
        path,
        name,
        mat,
        fits,
        solid.as_ref().map(|(p, t)| (*p, t.as_str())),
    )?;
    super::atomic::write_atomic(path, text.as_bytes())
}

/// The text of the `.mat.step` file to be written at `path` (see [`write_mat_step`]); `solid`
/// is the input file's path (for error messages) and text.
pub fn mat_step_text(
    path: &Path,
    name: &str,
    mat: &MedialAxis,
    (fits, degenerate_fits): (&[SeamFit], &[Option<SeamFit>]),
    solid: Option<(&Path, &str)>,
) -> Result<String> {
    let file_name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let mut w = Writer {
        path: path.to_path_buf(),
        ..Writer::default()
    };
    let apd = w.next_id();
    let app = w.next_id();
    w.push(
        apd,
        format!("APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"),
    );
    w.push(
        app,
        "APPLICATION_CONTEXT('core data for automotive mechanical design processes')".into(),
    );
    let sdr = w.next_id();
    let pds = w.next_id();
    let pd = w.next_id();
    let pdf = w.next_id();
    let product = w.next_id();
    let pc = w.next_id();
    let pdc = w.next_id();
    let rep = w.next_id();
    w.push(
        sdr,
        format!("SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})"),
    );
    w.push(pds, format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
    w.push(pd, format!("PRODUCT_DEFINITION('design','',#{pdf},#{pdc})"));
    w.push(
        pdf,
        format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"),
    );
    let pname = string(&format!("{name} medial axis"));
    w.push(
        product,
        format!("PRODUCT({pname},{pname},'seams and junctions traced by matrace',(#{pc}))"),
    );
    w.push(pc, format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    w.push(
        pdc,
        format!("PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"),
    );
    let mut items = vec![w.axis_placement()];
    let mut curves = vec![];
    for (seam, fit) in mat.seams.iter().zip(fits) {
        curves.push(w.bspline_curve(&format!("seam {}", seam.id), fit)?);
    }
    items.extend(w.curve_set("seams", &curves));
    let mut lines = vec![];
    for k in &mat.skeletal_edges {
        let name = format!("skeletal edge {}", k.id);
        let (Some(a), Some(b)) = (k.balls.first(), k.balls.last()) else {
            continue;
        };
        lines.push(w.line(&name, [a[0], a[1], a[2]], [b[0], b[1], b[2]])?);
    }
    items.extend(w.curve_set("skeletal edges", &lines));
    let mut degenerate = vec![];
    for (i, fit) in degenerate_fits.iter().enumerate() {
        if let Some(fit) = fit {
            degenerate.push(w.bspline_curve(&format!("degenerate curve {i}"), fit)?);
        }
    }
    items.extend(w.curve_set("degenerate curves", &degenerate));
    let mut points = vec![];
    for j in &mat.junctions {
        points.push(w.point(&format!("junction {}", j.id), j.point)?);
    }
    items.extend(w.curve_set("junctions", &points));
    let ctx = w.unit_context();
    w.push(
        rep,
        format!(
            "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('medial axis',({}),#{ctx})",
            refs(&items)
        ),
    );
    let cat = w.next_id();
    w.push(
        cat,
        format!("PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{product}))"),
    );
    if let Some((input, text)) = solid {
        let body = renumber_data_section(text, w.last_id()).map_err(|reason| Error::Syntax {
            path: input.to_path_buf(),
            reason,
        })?;
        w.data.push_str(body.trim_matches(['\n', '\r']));
        w.data.push('\n');
    }
    let mut out = String::new();
    out.push_str("ISO-10303-21;\nHEADER;\n");
    out.push_str(
        "FILE_DESCRIPTION(('matrace medial axis transform: seams and junctions'),'2;1');\n",
    );
    let _ = writeln!(
        out,
        "FILE_NAME({},'{}',(''),(''),'matrace {}','matrace','');",
        string(file_name),
        timestamp(),
        env!("CARGO_PKG_VERSION")
    );
    out.push_str("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n");
    out.push_str(&w.data);
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok(out)
}

/// Entity instances in the order they are written, with sequential ids.
#[derive(Default)]
struct Writer {
    /// The file being written (for error messages).
    path: std::path::PathBuf,
    data: String,
    last: u64,
}

impl Writer {
    fn next_id(&mut self) -> u64 {
        self.last += 1;
        self.last
    }

    fn last_id(&self) -> u64 {
        self.last
    }

    fn push(&mut self, id: u64, entity: String) {
        let _ = writeln!(self.data, "#{id} = {entity};");
    }

    fn point(&mut self, name: &str, p: [f64; 3]) -> Result<u64, Error> {
        let id = self.next_id();
        let coords = p.iter().map(|v| real(*v)).collect::<Option<Vec<_>>>();
        let coords = coords.ok_or_else(|| self.not_finite(name))?;
        self.push(
            id,
            format!("CARTESIAN_POINT({},({}))", string(name), coords.join(",")),
        );
        Ok(id)
    }

    fn bspline_curve(&mut self, name: &str, fit: &SeamFit) -> Result<u64, Error> {
        let ctrl = fit
            .control_points
            .iter()
            .map(|c| self.point("", *c))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| self.not_finite(name))?;
        let (knots, mults) = fit.knots_with_multiplicities();
        let knots = knots
            .iter()
            .map(|k| real(*k))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| self.not_finite(name))?;
        let mults: Vec<String> = mults.iter().map(|m| m.to_string()).collect();
        let closed = fit.control_points.first() == fit.control_points.last();
        let id = self.next_id();
        self.push(
            id,
            format!(
                "B_SPLINE_CURVE_WITH_KNOTS({},{},({}),.UNSPECIFIED.,{},.F.,({}),({}),.UNSPECIFIED.)",
                string(name),
                fit.degree,
                refs(&ctrl),
                if closed { ".T." } else { ".F." },
                mults.join(","),
                knots.join(",")
            ),
        );
        Ok(id)
    }

    /// A `GEOMETRIC_CURVE_SET` named `name` of `members`; none when there are none.
    fn curve_set(&mut self, name: &str, members: &[u64]) -> Option<u64> {
        if members.is_empty() {
            return None;
        }
        let id = self.next_id();
        self.push(
            id,
            format!("GEOMETRIC_CURVE_SET({},({}))", string(name), refs(members)),
        );
        Some(id)
    }

    /// A straight line from `a` to `b`: a B-spline of degree 1 with two control points.
    fn line(&mut self, name: &str, a: [f64; 3], b: [f64; 3]) -> Result<u64, Error> {
        let ends = [self.point("", a), self.point("", b)];
        let [Ok(a), Ok(b)] = ends else {
            return Err(self.not_finite(name));
        };
        let id = self.next_id();
        self.push(
            id,
            format!(
                "B_SPLINE_CURVE_WITH_KNOTS({},1,(#{a},#{b}),.POLYLINE_FORM.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.)",
                string(name)
            ),
        );
        Ok(id)
    }

    fn not_finite(&self, name: &str) -> Error {
        Error::Model {
            path: self.path.clone(),
            reason: format!("{name}: a coordinate is not finite"),
        }
    }

    fn axis_placement(&mut self) -> u64 {
        let id = self.next_id();
        let (o, z, x) = (self.next_id(), self.next_id(), self.next_id());
        self.push(id, format!("AXIS2_PLACEMENT_3D('',#{o},#{z},#{x})"));
        self.push(o, "CARTESIAN_POINT('',(0.,0.,0.))".into());
        self.push(z, "DIRECTION('',(0.,0.,1.))".into());
        self.push(x, "DIRECTION('',(1.,0.,0.))".into());
        id
    }

    /// Millimetre, radian and steradian units and the uncertainty, as OCCT writes them.
    fn unit_context(&mut self) -> u64 {
        let ctx = self.next_id();
        let (mm, rad, sr, unc) = (
            self.next_id(),
            self.next_id(),
            self.next_id(),
            self.next_id(),
        );
        self.push(
            ctx,
            format!(
                "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{unc})) \
                 GLOBAL_UNIT_ASSIGNED_CONTEXT((#{mm},#{rad},#{sr})) \
                 REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY') )"
            ),
        );
        self.push(
            mm,
            "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )".into(),
        );
        self.push(
            rad,
            "( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )".into(),
        );
        self.push(
            sr,
            "( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )".into(),
        );
        self.push(
            unc,
            format!(
                "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{mm},'distance_accuracy_value','confusion accuracy')",
                real(UNCERTAINTY).expect("finite")
            ),
        );
        ctx
    }
}

fn refs(ids: &[u64]) -> String {
    ids.iter()
        .map(|i| format!("#{i}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// A STEP REAL: the shortest decimal that reads back to the same `f64`, with the point and
/// exponent STEP requires (`1.`, `2.5E-07`); `None` for NaN and infinities.
pub fn real(x: f64) -> Option<String> {
    if !x.is_finite() {
        return None;
    }
    let s = format!("{x:?}");
    let (mantissa, exponent) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), Some(e.to_string())),
        None => (s, None),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').to_string()
    } else {
        format!("{mantissa}.")
    };
    Some(match exponent {
        Some(e) => format!("{mantissa}E{e}"),
        None => mantissa,
    })
}

/// A STEP string literal: quotes doubled, backslashes escaped, anything outside printable
/// ASCII replaced by `_`.
fn string(s: &str) -> String {
    let mut out = String::from("'");
    for c in s.chars() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            _ => out.push('_'),
        }
    }
    out.push('\'');
    out
}

/// The UTC write time as ISO 8601 (`2026-11-22T05:29:08`): now, or `SOURCE_DATE_EPOCH`
/// (seconds) when set, the reproducible-builds convention, so that a batch can produce files
/// identical byte for byte.
fn timestamp() -> String {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs() as i64)
                .unwrap_or(0)
        });
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (H. Hinnant, "chrono-Compatible Low-Level Date
    // Algorithms", days_from_civil's inverse).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// The entity instances of `text`'s (first) DATA section, with every instance name and
/// reference `#n` outside strings and comments replaced by `#(n + offset)`.
pub fn renumber_data_section(text: &str, offset: u64) -> Result<String, String> {
    let b = text.as_bytes();
    let mut i = 0;
    let mut out = String::new();
    let mut in_data = false;
    let mut copied_from = 0;
    while i < b.len() {
        match b[i] {
            b'\'' => {
                // A string: '' is an escaped quote.
                i += 1;
                loop {
                    match b.get(i) {
                        None => return Err("unterminated string".into()),
                        Some(b'\'') if b.get(i + 1) == Some(&b'\'') => i += 2,
                        Some(b'\'') => break,
                        Some(_) => i += 1,
                    }
                }
                i += 1;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..]
                    .find("*/")
                    .map(|k| i + 2 + k + 2)
                    .ok_or("unterminated comment")?;
            }
            b'#' if in_data && b.get(i + 1).is_some_and(u8::is_ascii_digit) => {
                let start = i + 1;
                let mut end = start;
                while end < b.len() && b[end].is_ascii_digit() {
                    end += 1;
                }
                let n: u64 = text[start..end]
                    .parse()
                    .map_err(|_| format!("bad instance name #{}", &text[start..end]))?;
                out.push_str(&text[copied_from..i]);
                let _ = write!(out, "#{}", n + offset);
                copied_from = end;
                i = end;
            }
            c if c.is_ascii_alphabetic() && (i == 0 || !is_word(b[i - 1])) => {
                let mut end = i;
                while end < b.len() && is_word(b[end]) {
                    end += 1;
                }
                let word = &text[i..end];
                if !in_data && word == "DATA" {
                    // `DATA;` (or AP242's `DATA(...);`): the section starts after the `;`.
                    let semi = text[end..].find(';').ok_or("DATA without ';'")?;
                    in_data = true;
                    copied_from = end + semi + 1;
                    i = copied_from;
                    continue;
                }
                if in_data && word == "ENDSEC" {
                    out.push_str(&text[copied_from..i]);
                    return Ok(out);
                }
                i = end;
            }
            _ => i += 1,
        }
    }
    Err(if in_data {
        "DATA section without ENDSEC".into()
    } else {
        "no DATA section".into()
    })
}

fn is_word(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_' || c == b'-'
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_are_step_reals_and_read_back_exactly() {
        assert_eq!(real(1.0).unwrap(), "1.");
        assert_eq!(real(-0.5).unwrap(), "-0.5");
        assert_eq!(real(1e-7).unwrap(), "1.E-7");
        assert_eq!(real(2.5e20).unwrap(), "2.5E20");
        assert_eq!(real(0.1 + 0.2).unwrap(), "0.30000000000000004");
        assert!(real(f64::NAN).is_none() && real(f64::INFINITY).is_none());
        for x in [std::f64::consts::PI, 1.0 / 3.0, 123456.789e-12, -9.87e15] {
            let s = real(x).unwrap().replace("E", "e");
            assert_eq!(s.parse::<f64>().unwrap(), x);
        }
    }

    #[test]
    fn strings_are_escaped() {
        assert_eq!(string("it's"), "'it''s'");
        assert_eq!(string("a\\b"), "'a\\\\b'");
        assert_eq!(string("Maß"), "'Ma_'");
    }

    #[test]
    fn timestamps_are_iso_8601() {
        let t = timestamp();
        assert_eq!(t.len(), 19, "{t}");
        assert_eq!(&t[4..5], "-");
        assert_eq!(&t[10..11], "T");
        assert!(t[..4].parse::<u32>().unwrap() >= 2024, "{t}");
    }

    #[test]
    fn renumbering_skips_strings_comments_and_the_header() {
        let text = "ISO-10303-21;\nHEADER;\nFILE_NAME('#1 DATA; ENDSEC;');\nENDSEC;\nDATA;\n\
                    #1 = PRODUCT('a #2 ''#3''',/* #4 */ #2);\n#2=FOO(#1,(#10,#2));\nENDSEC;\n\
                    END-ISO-10303-21;\n";
        let body = renumber_data_section(text, 100).unwrap();
        assert_eq!(
            body,
            "\n#101 = PRODUCT('a #2 ''#3''',/* #4 */ #102);\n#102=FOO(#101,(#110,#102));\n"
        );
        assert!(renumber_data_section("HEADER; ENDSEC;", 5).is_err());
        assert!(renumber_data_section("DATA; #1=A('x);", 5).is_err());
    }
}
