//! Every quantitative claim of the three seed documents (000, 002, 003), kept here
//! as data: its id, section, text and figure, and a function that answers it from
//! the measured rows of the report and the specular table, with a verdict and one
//! line of why. Speed verdicts are read from the MCU instruction counts
//! (deterministic); host time is shown beside them, never decides. A claim that no
//! configuration answers says so in its row.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::image::compare::Verdict as Nmse;
use crate::scene::desc::{Named, ShadingName, SpanName};
use crate::tables::report::mcu::BOARDS;
use crate::tables::report::model::{instr, med_instr, median_f, of};
use crate::tables::report::model::{Config, Kind, ReportOptions, Row};

/// The verdict of a claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Measured, and it holds.
    Holds,
    /// Measured; it holds on part of the range, one core, or below the figure.
    InPart,
    /// Measured, and it does not hold.
    DoesNotHold,
    /// No configuration of the report answers it.
    NotMeasured,
}

impl Verdict {
    /// The word in the table.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::InPart => "holds in part",
            Verdict::DoesNotHold => "does not hold",
            Verdict::NotMeasured => "not measured here",
        }
    }
}

/// One row of `docs/specular.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecRow {
    /// Model name.
    pub model: String,
    /// Exponent.
    pub n: u32,
    /// Max |model − cⁿ|.
    pub max_abs: f64,
    /// Max |model − cⁿ| over the epicentre.
    pub abs_epi: f64,
    /// Max relative error over the epicentre.
    pub rel_epi: f64,
    /// Max relative error over the decay zone.
    pub rel_decay: f64,
    /// NMSE on the sphere and on the teapot.
    pub nmse: [f64; 2],
    /// Host ns per evaluation.
    pub ns_per_eval: f64,
}

/// What the claims read besides the report's rows: the specular table and the
/// specular models' instruction counts.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    /// Rows of `docs/specular.csv`.
    pub spec: Vec<SpecRow>,
    /// Instructions per evaluation by (board, model, n), `docs/mcu-specular.csv`.
    pub mcu_spec: HashMap<(String, String, u32), f64>,
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// Columns of a CSV header by name.
fn columns(path: &Path, header: &str, names: &[&str]) -> Result<Vec<usize>, String> {
    let h: Vec<&str> = header.split(',').collect();
    names
        .iter()
        .map(|n| {
            h.iter()
                .position(|x| x == n)
                .ok_or_else(|| format!("{}: no column `{n}`", path.display()))
        })
        .collect()
}

impl Inputs {
    /// Reads the specular table and the specular instruction counts of `opts`.
    pub fn read(opts: &ReportOptions) -> Result<Inputs, String> {
        Ok(Inputs {
            spec: parse_spec(&opts.specular_csv, &read(&opts.specular_csv)?)?,
            mcu_spec: parse_mcu_spec(&opts.mcu_specular_csv, &read(&opts.mcu_specular_csv)?)?,
        })
    }
}

/// Parses `specular.csv` (columns by name).
pub fn parse_spec(path: &Path, text: &str) -> Result<Vec<SpecRow>, String> {
    let mut lines = text.lines();
    let c = columns(
        path,
        lines.next().unwrap_or(""),
        &[
            "model",
            "n",
            "max_abs",
            "max_abs_epicentre",
            "max_rel_epicentre",
            "max_rel_decay",
            "nmse_sphere",
            "nmse_teapot",
            "ns_per_eval",
        ],
    )?;
    lines
        .enumerate()
        .map(|(i, l)| {
            let v: Vec<&str> = l.split(',').collect();
            let f = |k: usize| {
                v.get(c[k])
                    .and_then(|x| x.parse::<f64>().ok())
                    .ok_or_else(|| {
                        format!(
                            "{} line {}: column {} is not a number",
                            path.display(),
                            i + 2,
                            k
                        )
                    })
            };
            Ok(SpecRow {
                model: v.get(c[0]).unwrap_or(&"").to_string(),
                n: f(1)? as u32,
                max_abs: f(2)?,
                abs_epi: f(3)?,
                rel_epi: f(4)?,
                rel_decay: f(5)?,
                nmse: [f(6)?, f(7)?],
                ns_per_eval: f(8)?,
            })
        })
        .collect()
}

/// Parses `mcu-specular.csv`: `board,model,n,evals,instructions,per_eval`.
pub fn parse_mcu_spec(
    path: &Path,
    text: &str,
) -> Result<HashMap<(String, String, u32), f64>, String> {
    let mut lines = text.lines();
    let c = columns(
        path,
        lines.next().unwrap_or(""),
        &["board", "model", "n", "per_eval"],
    )?;
    let mut m = HashMap::new();
    for (i, l) in lines.enumerate() {
        let v: Vec<&str> = l.split(',').collect();
        let bad = || format!("{} line {}: malformed row `{l}`", path.display(), i + 2);
        let n = v
            .get(c[2])
            .and_then(|x| x.parse::<u32>().ok())
            .ok_or_else(bad)?;
        let pe = v
            .get(c[3])
            .and_then(|x| x.parse::<f64>().ok())
            .ok_or_else(bad)?;
        m.entry((v[c[0]].to_string(), v[c[1]].to_string(), n))
            .or_insert(pe);
    }
    Ok(m)
}

/// What a claim's function answers: our figures and the verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    /// Our error figure (NMSE, relative error, …), or empty.
    pub error: String,
    /// ARMv6-M instructions (per pixel or per evaluation), or empty.
    pub v6m: String,
    /// Cortex-M4 instructions, or empty.
    pub m4: String,
    /// Host ns, or empty.
    pub host: String,
    /// The verdict.
    pub verdict: Verdict,
    /// One line of why.
    pub why: String,
}

/// The measured data a claim reads.
pub struct Ctx<'a> {
    /// The report's rows.
    pub rows: &'a [Row],
    /// The specular inputs.
    pub inputs: &'a Inputs,
}

/// A seed claim.
pub struct Claim {
    /// Short id.
    pub id: &'static str,
    /// Seed and section.
    pub section: &'static str,
    /// The claim in a line.
    pub text: &'static str,
    /// The seed's figure.
    pub seed: &'static str,
    /// Answers it from the measurements.
    pub answer: fn(&Ctx) -> Answer,
}

fn not_here(why: &str) -> Answer {
    Answer {
        error: String::new(),
        v6m: String::new(),
        m4: String::new(),
        host: String::new(),
        verdict: Verdict::NotMeasured,
        why: why.to_string(),
    }
}

fn pct(x: f64) -> String {
    format!("{:.2} %", x * 100.0)
}

fn sci(x: f64) -> String {
    crate::tables::report::model::sci(x)
}

/// Verdict of a claimed speed-up `claimed` (×) against our speed-ups on the two
/// cores: holds when both reach 90 % of it, in part when one does or both are
/// faster at all, else does not hold.
fn speed_verdict(claimed: f64, ours: [f64; 2]) -> (Verdict, String) {
    let reach = ours.iter().filter(|&&x| x >= 0.9 * claimed).count();
    let v = match reach {
        2 => Verdict::Holds,
        1 => Verdict::InPart,
        _ if ours.iter().any(|&x| x > 1.02) => Verdict::InPart,
        _ => Verdict::DoesNotHold,
    };
    let why = match v {
        Verdict::Holds => format!("at least 90 % of {claimed}× on both cores"),
        Verdict::InPart if reach == 1 => format!("{claimed}× reached on one core only"),
        Verdict::InPart => format!("faster, but below {claimed}× on both cores"),
        _ => "no speed-up in instructions on either core".to_string(),
    };
    (v, why)
}

fn span(rows: &[Row], sp: SpanName) -> Vec<&Row> {
    of(rows, &|c: &Config| c.kind == Kind::Span && c.span == sp)
}

fn shading(rows: &[Row], sh: ShadingName) -> Vec<&Row> {
    of(rows, &|c: &Config| {
        (c.kind == Kind::Shading || (c.kind == Kind::Span && c.span == SpanName::GRADIENT))
            && c.shading == sh
    })
}

/// A speed claim: `method` against `base`, speed-up = base cost / method cost.
fn speed(method: &[&Row], base: &[&Row], claimed: f64, what: &str) -> Answer {
    if method.is_empty() || base.is_empty() {
        return not_here("the report run lacks these rows");
    }
    let up: [f64; 2] = [0, 1].map(|k| med_instr(base, k) / med_instr(method, k));
    let host = |rs: &[&Row]| median_f(rs.iter().map(|r| r.ns_per_px).collect());
    let (verdict, why) = speed_verdict(claimed, up);
    Answer {
        error: String::new(),
        v6m: format!(
            "{} vs {} ({:.2}×)",
            instr(med_instr(method, 0)),
            instr(med_instr(base, 0)),
            up[0]
        ),
        m4: format!(
            "{} vs {} ({:.2}×)",
            instr(med_instr(method, 1)),
            instr(med_instr(base, 1)),
            up[1]
        ),
        host: format!("{:.2} vs {:.2} ns/px", host(method), host(base)),
        verdict,
        why: format!("{what}: {why}"),
    }
}

fn spec_rows<'a>(ctx: &'a Ctx, model: &str) -> Vec<&'a SpecRow> {
    ctx.inputs
        .spec
        .iter()
        .filter(|r| r.model == model)
        .collect()
}

/// Max of `f` over the rows of `model` and the n where it is reached.
fn spec_max(ctx: &Ctx, model: &str, f: impl Fn(&SpecRow) -> f64) -> Option<(f64, u32)> {
    spec_rows(ctx, model)
        .into_iter()
        .map(|r| (f(r), r.n))
        .fold(None, |a, b| match a {
            Some(a) if a.0 >= b.0 => Some(a),
            _ => Some(b),
        })
}

/// A bound claim on a specular-table quantity: holds when the max over n is
/// within `bound`.
fn spec_bound(
    ctx: &Ctx,
    model: &str,
    bound: f64,
    f: fn(&SpecRow) -> f64,
    what: &str,
    as_pct: bool,
) -> Answer {
    let Some((m, n)) = spec_max(ctx, model, f) else {
        return not_here("docs/specular.csv has no rows of this model");
    };
    let show = |x: f64| if as_pct { pct(x) } else { sci(x) };
    Answer {
        error: format!("{} (n = {n})", show(m)),
        verdict: if m <= bound {
            Verdict::Holds
        } else {
            Verdict::DoesNotHold
        },
        why: format!(
            "largest {what} over n = 1 … 1000 {} {}",
            if m <= bound { "is within" } else { "exceeds" },
            show(bound)
        ),
        ..not_here("")
    }
}

/// Median over n of the instructions per evaluation of `a` over `b` on `board`.
fn eval_ratio(ctx: &Ctx, board: &str, a: &str, b: &str) -> Option<f64> {
    let mut v = Vec::new();
    for r in spec_rows(ctx, a) {
        let x = ctx
            .inputs
            .mcu_spec
            .get(&(board.to_string(), a.to_string(), r.n))?;
        let y = ctx
            .inputs
            .mcu_spec
            .get(&(board.to_string(), b.to_string(), r.n))?;
        v.push(x / y);
    }
    (!v.is_empty()).then(|| median_f(v))
}

/// The claims, in the order of the seeds.
pub fn claims() -> Vec<Claim> {
    vec![
        Claim { id: "incr-ops-4v5", section: "000 §2.1", text: "ΔI by (2.15) needs 4 multiply/divide operations, by the determinant form (2.16) 5", seed: "4 vs 5",
            answer: |_| not_here("only the determinant form (2.16) is implemented; its cost is in the setup's instructions") },
        Claim { id: "bp-exact", section: "000 §2.2", text: "interpolating over БП instead of the true length leaves every segment point and the scanline ΔI exact", seed: "δ = 0",
            answer: |ctx| {
                let g = span(ctx.rows, SpanName::GRADIENT);
                let n = g.iter().map(|r| r.nmse).fold(0.0, f64::max);
                let mx = g.iter().map(|r| r.max_channel_error).max().unwrap_or(0);
                Answer { error: format!("NMSE {} (max channel error {mx})", sci(n)),
                    verdict: if n == 0.0 { Verdict::Holds } else if Nmse::from_nmse(n) == Nmse::Indistinguishable { Verdict::InPart } else { Verdict::DoesNotHold },
                    why: "exact in exact arithmetic; what is left in `gradient` is fixed-point and 8-bit rounding".into(), ..not_here("") } } },
        Claim { id: "stepper-err-half", section: "000 §2.2, §4.3", text: "a stepped pixel lies 0 … ½ pixel from the ideal line; an edge takes БП steps", seed: "0 … 1/2",
            answer: |ctx| {
                let cov: usize = span(ctx.rows, SpanName::GRADIENT).iter().map(|r| r.coverage_mismatch).sum();
                Answer { error: format!("coverage mismatch {cov} px"), verdict: if cov == 0 { Verdict::Holds } else { Verdict::DoesNotHold },
                    why: "the edge walker picks every pixel centre the f64 edges cover (top-left rule)".into(), ..not_here("") } } },
        Claim { id: "interior-err-max", section: "000 §2.2 (2.27)", text: "error of an interior point ≤ |I_C − I_A| / (2·МП_AC)", seed: "≤ |ΔI|/(2·МП)",
            answer: |_| not_here("a per-triangle bound; the report gives the max channel error per figure, not per triangle") },
        Claim { id: "counter-2x", section: "000 §3.1", text: "two interpolators from both span ends double the scanline speed", seed: "2×",
            answer: |ctx| speed(&span(ctx.rows, SpanName::named("counter")), &span(ctx.rows, SpanName::GRADIENT), 2.0, "`counter` against `gradient`") },
        Claim { id: "even-odd-2x", section: "000 §3.1–3.2", text: "even/odd interpolators stepping 2ΔI double the scanline speed", seed: "2×",
            answer: |ctx| speed(&span(ctx.rows, SpanName::named("even-odd")), &span(ctx.rows, SpanName::GRADIENT), 2.0, "`even-odd` against `gradient`") },
        Claim { id: "kway-max4", section: "000 §3.1", text: "the best number of interpolators is at most 4", seed: "k ≤ 4",
            answer: |ctx| {
                let best = |names: &[&str], k: usize| names.iter().map(|n| med_instr(&span(ctx.rows, SpanName::named(n)), k)).fold(f64::INFINITY, f64::min);
                let kway = ["kway2", "kway3", "kway4"];
                let seg = ["segment8", "segment16", "segment32", "segment64"];
                let c: [(f64, f64); 2] = [0, 1].map(|k| (best(&kway, k), best(&seg, k)));
                let wins = c.iter().filter(|(a, b)| a <= b).count();
                Answer { v6m: format!("k ≤ 4 {} vs k > 4 {}", instr(c[0].0), instr(c[0].1)), m4: format!("k ≤ 4 {} vs k > 4 {}", instr(c[1].0), instr(c[1].1)),
                    verdict: match wins { 2 => Verdict::Holds, 1 => Verdict::InPart, _ => Verdict::DoesNotHold },
                    why: "cheapest `kway2`–`kway4` against cheapest segment with more than 4 units".into(), ..not_here("") } } },
        Claim { id: "even-odd-err", section: "000 App. Б", text: "even/odd accumulates ¾·z·2^−(V+1) less truncation error than classic", seed: "¾·z·2^−(V+1)",
            answer: |ctx| {
                let same = span(ctx.rows, SpanName::named("even-odd")).iter().all(|r| r.same_as_gradient);
                Answer { error: format!("same image as `gradient`: {}", if same { "yes" } else { "no" }), ..not_here("the accumulators do not truncate, so there is no error to save") } } },
        Claim { id: "segment-width", section: "000 App. Б", text: "p units fill a segment of w pixels", seed: "2, 4, 8, 14, 22, 32",
            answer: |_| not_here("a formula, checked by the `segment_width` doctest rather than by a configuration") },
        Claim { id: "sierp-4x", section: "000 §3.3", text: "shading one of four sub-triangles and replicating it is ≈ 4× faster", seed: "≈ 4×",
            answer: |ctx| speed(&span(ctx.rows, SpanName::named("sierpinski")), &span(ctx.rows, SpanName::GRADIENT), 4.0, "`sierpinski` against `gradient`") },
        Claim { id: "sierp-hw", section: "000 §3.3", text: "needs 4 row, 2 line and 1 code interpolators and 3 adders", seed: "4 + 2 + 1 + 3",
            answer: |_| not_here("hardware units") },
        Claim { id: "sierp-err-classic", section: "000 §3.3, table 3.1", text: "with vertices snapped to one parity the error equals classic Gouraud's", seed: "= classic",
            answer: |ctx| {
                let s = span(ctx.rows, SpanName::named("sierpinski"));
                let c = span(ctx.rows, SpanName::CLASSIC);
                let (a, b) = (median_f(s.iter().map(|r| r.nmse).collect()), median_f(c.iter().map(|r| r.nmse).collect()));
                Answer { error: format!("{} vs classic {}", sci(a), sci(b)), verdict: if a <= 1.1 * b { Verdict::Holds } else { Verdict::DoesNotHold },
                    why: "the snapping moves vertices, so coverage and colours change; `sierpinski-exact` (no snapping) is exact".into(), ..not_here("") } } },
        Claim { id: "sierp-time-appG", section: "000 App. Г", text: "shading time modified vs base: sphere 4 vs 8, teapot 10 vs 17, robot 15 vs 22", seed: "1.47× … 2.0×",
            answer: |ctx| speed(&span(ctx.rows, SpanName::named("sierpinski")), &span(ctx.rows, SpanName::CLASSIC), 1.47, "`sierpinski` against `classic`") },
        Claim { id: "sierp-nmse-appG", section: "000 App. Г", text: "NMSE against the base: sphere 5.8e-4, teapot 8.6e-4, robot 9.5e-4", seed: "5.8e-4 … 9.5e-4",
            answer: |ctx| {
                let s = span(ctx.rows, SpanName::named("sierpinski"));
                let m = s.iter().map(|r| r.nmse).fold(0.0, f64::max);
                let each: Vec<String> = s.iter().map(|r| format!("{} {}", r.figure, sci(r.nmse))).collect();
                Answer { error: each.join(", "), verdict: if m <= 9.5e-4 { Verdict::Holds } else { Verdict::DoesNotHold },
                    why: if m <= 9.5e-4 { "no figure is worse than the seed's worst".into() } else { "worse than the seed's worst figure".into() }, ..not_here("") } } },
        Claim { id: "quad-fd-12x", section: "003 conclusions", text: "forward differences make the quadratic surface 12× faster", seed: "12×",
            answer: |_| not_here("there is no direct-evaluation variant to compare with") },
        Claim { id: "quad-no-mul", section: "003 (5)–(7)", text: "no multiplication per pixel; four units fill a 2×2 block", seed: "0 mul/px",
            answer: |_| not_here("an instruction mix, read from the disassembly rather than a configuration") },
        Claim { id: "phong-eo-2x", section: "003 conclusions", text: "independent even/odd points double Phong shading speed", seed: "2×",
            answer: |ctx| speed(&shading(ctx.rows, ShadingName::PHONG_EVEN_ODD), &shading(ctx.rows, ShadingName::PHONG), 2.0, "`phong-even-odd` against `phong`") },
        Claim { id: "schlick-rel", section: "002 §2.1", text: "Schlick's relative error ≤ 3.2 % over the epicentre", seed: "≤ 3.2 %",
            answer: |ctx| spec_bound(ctx, "schlick", 0.032, |r| r.rel_epi, "epicentre relative error", true) },
        Claim { id: "schlick-mod-rel", section: "002 §2.7 (3.2 %), §3.4 (0.4 %)", text: "modified Schlick's relative error in the highlight ≤ 3.2 % / ≤ 0.4 % (Schlick 10 %)", seed: "≤ 3.2 % / ≤ 0.4 %",
            answer: |ctx| {
                let mut a = spec_bound(ctx, "schlick-mod", 0.004, |r| r.rel_epi, "epicentre relative error", true);
                if a.verdict == Verdict::DoesNotHold && spec_max(ctx, "schlick-mod", |r| r.rel_epi).is_some_and(|m| m.0 <= 0.032) {
                    a.verdict = Verdict::InPart;
                    a.why = "within 3.2 % (§2.7), not within 0.4 % (§3.4)".into();
                }
                a } },
        Claim { id: "schlick-mod-6.8", section: "002 §2.1", text: "its relative error differs from Schlick's by 6.8 %", seed: "6.8 %",
            answer: |ctx| {
                let a = spec_max(ctx, "schlick", |r| r.rel_epi);
                let b = spec_max(ctx, "schlick-mod", |r| r.rel_epi);
                let (Some(a), Some(b)) = (a, b) else { return not_here("docs/specular.csv lacks the rows") };
                let d = a.0 - b.0;
                Answer { error: pct(d), verdict: if (d - 0.068).abs() <= 0.01 { Verdict::Holds } else { Verdict::DoesNotHold },
                    why: "largest epicentre relative errors, Schlick minus modified; holds within one point".into(), ..not_here("") } } },
        Claim { id: "schlick-mod-nmse", section: "002 table 3.2", text: "modified Schlick's largest NMSE on the test figures", seed: "1.1e-4",
            answer: |ctx| spec_bound(ctx, "schlick-mod", 1.1e-4, |r| r.nmse[0].max(r.nmse[1]), "NMSE on sphere and teapot", false) },
        Claim { id: "quad-a-table", section: "002 §2.2", text: "a(n) is a precomputed table for n ∈ [1, 1000]", seed: "1000 entries",
            answer: |_| not_here("a table built at compile time and tested against f64, not a configuration") },
        Claim { id: "quad-rel-2", section: "002 conclusions", text: "the quadratic model's epicentre relative error ≤ 2 %", seed: "≤ 2 %",
            answer: |ctx| spec_bound(ctx, "quadratic", 0.02, |r| r.rel_epi, "epicentre relative error", true) },
        Claim { id: "quad-epi-10x", section: "002 §3.4", text: "the quadratic model is over 10× more accurate than Schlick in the epicentre", seed: "> 10×",
            answer: |ctx| {
                let q = spec_rows(ctx, "quadratic");
                let r: Vec<f64> = q.iter().filter(|r| r.n >= 4).filter_map(|qr| spec_rows(ctx, "schlick").into_iter().find(|s| s.n == qr.n).map(|s| s.abs_epi / qr.abs_epi)).collect();
                if r.is_empty() { return not_here("docs/specular.csv lacks the rows") }
                let (lo, md) = (r.iter().copied().fold(f64::INFINITY, f64::min), median_f(r.clone()));
                Answer { error: format!("{lo:.1}× … median {md:.1}×"), verdict: if lo > 10.0 { Verdict::Holds } else if md > 10.0 { Verdict::InPart } else { Verdict::DoesNotHold },
                    why: "Schlick's over the quadratic's largest epicentre absolute error, n ≥ 4".into(), ..not_here("") } } },
        Claim { id: "quad-nmse", section: "002 table 3.2", text: "the quadratic model's NMSE ≤ 2.6e-4 for n < 170, < 2e-4 otherwise", seed: "2.6e-4; < 2e-4",
            answer: |ctx| {
                let q = spec_rows(ctx, "quadratic");
                if q.is_empty() { return not_here("docs/specular.csv lacks the rows") }
                let m = |lo: bool| q.iter().filter(|r| (r.n < 170) == lo).map(|r| r.nmse[0].max(r.nmse[1])).fold(0.0, f64::max);
                let (a, b) = (m(true), m(false));
                let ok = [a <= 2.6e-4, b < 2e-4];
                Answer { error: format!("{} (n < 170), {} (n ≥ 170)", sci(a), sci(b)),
                    verdict: match ok { [true, true] => Verdict::Holds, [false, false] => Verdict::DoesNotHold, _ => Verdict::InPart },
                    why: "largest NMSE on sphere and teapot in each range of n".into(), ..not_here("") } } },
        Claim { id: "cq-rel-3", section: "002 §2.2, §2.7, §3.1", text: "cosine-quadratic relative error ≤ 3 % in the epicentre and the decay zone", seed: "≤ 3 %",
            answer: |ctx| {
                let (Some(e), Some(d)) = (spec_max(ctx, "cos-quad", |r| r.rel_epi), spec_max(ctx, "cos-quad", |r| r.rel_decay)) else { return not_here("docs/specular.csv lacks the rows") };
                Answer { error: format!("epicentre {}, decay zone {}", pct(e.0), pct(d.0)),
                    verdict: match (e.0 <= 0.03, d.0 <= 0.03) { (true, true) => Verdict::Holds, (true, false) => Verdict::InPart, _ => Verdict::DoesNotHold },
                    why: "largest over n = 1 … 1000 in each zone".into(), ..not_here("") } } },
        Claim { id: "cq-bloom-0.1", section: "002 §2.3", text: "cosine-quadratic absolute error in the bloom zone ≤ 0.1", seed: "≤ 0.1",
            answer: |ctx| spec_bound(ctx, "cos-quad", 0.1, |r| r.max_abs, "absolute error over all c", false) },
        Claim { id: "cq-abs-vs-schlick", section: "002 §3.1 (4×), §3.4 (3×)", text: "cosine-quadratic epicentre absolute error 3–4× smaller than Schlick's", seed: "3× … 4×",
            answer: |ctx| {
                let r: Vec<f64> = spec_rows(ctx, "cos-quad").iter().filter(|r| r.n >= 4).filter_map(|c| spec_rows(ctx, "schlick").into_iter().find(|s| s.n == c.n).map(|s| s.abs_epi / c.abs_epi)).collect();
                if r.is_empty() { return not_here("docs/specular.csv lacks the rows") }
                let (lo, hi) = (r.iter().copied().fold(f64::INFINITY, f64::min), r.iter().copied().fold(0.0, f64::max));
                Answer { error: format!("{lo:.2}× … {hi:.2}×"), verdict: if lo >= 3.0 { Verdict::Holds } else if hi >= 3.0 { Verdict::InPart } else { Verdict::DoesNotHold },
                    why: "Schlick's over cosine-quadratic's largest epicentre absolute error, n ≥ 4".into(), ..not_here("") } } },
        Claim { id: "cq-nmse", section: "002 table 3.2, §3.4", text: "cosine-quadratic's largest NMSE 8e-5 (below 1e-4)", seed: "8e-5",
            answer: |ctx| {
                let mut a = spec_bound(ctx, "cos-quad", 8e-5, |r| r.nmse[0].max(r.nmse[1]), "NMSE on sphere and teapot", false);
                if a.verdict == Verdict::DoesNotHold && spec_max(ctx, "cos-quad", |r| r.nmse[0].max(r.nmse[1])).is_some_and(|m| m.0 <= 1e-4) {
                    a.verdict = Verdict::InPart;
                    a.why = "above 8e-5 but below 1e-4 (indistinguishable)".into();
                }
                a } },
        Claim { id: "cq-vs-schlick-speed", section: "002 §3.1, §3.4", text: "cosine-quadratic is 1.7× faster than Schlick in software", seed: "1.7×",
            answer: |ctx| {
                let r: Vec<Option<f64>> = BOARDS.iter().map(|b| eval_ratio(ctx, b.0, "schlick", "cos-quad")).collect();
                let (Some(a), Some(b)) = (r[0], r[1]) else { return not_here("docs/mcu-specular.csv lacks Schlick or cosine-quadratic rows") };
                let host: Vec<f64> = spec_rows(ctx, "schlick").iter().filter_map(|s| spec_rows(ctx, "cos-quad").into_iter().find(|c| c.n == s.n).map(|c| s.ns_per_eval / c.ns_per_eval)).collect();
                let (verdict, why) = speed_verdict(1.7, [a, b]);
                Answer { v6m: format!("{a:.2}× per eval"), m4: format!("{b:.2}× per eval"), host: format!("{:.2}× per eval", median_f(host)), verdict,
                    why: format!("instructions per evaluation, Schlick over cosine-quadratic, median over n: {why}"), error: String::new() } } },
        Claim { id: "cq-frame-20", section: "002 §3.4 fig. 3.13", text: "frames up to 20 % faster than exact Blinn", seed: "≤ 20 %",
            answer: |ctx| {
                let spec = of(ctx.rows, &|c: &Config| c.kind == Kind::Specular);
                let save = |k: usize| spec.iter().filter(|r| r.config.specular.name() == "cos-quad").filter_map(|r| spec.iter().find(|e| e.config.specular.name() == "exact" && e.config.shininess == r.config.shininess && e.figure == r.figure).map(|e| 1.0 - r.mcu[k].per_pixel / e.mcu[k].per_pixel)).fold(f64::NEG_INFINITY, f64::max);
                let hs = spec.iter().filter(|r| r.config.specular.name() == "cos-quad").filter_map(|r| spec.iter().find(|e| e.config.specular.name() == "exact" && e.config.shininess == r.config.shininess && e.figure == r.figure).map(|e| 1.0 - r.ns_per_px / e.ns_per_px)).fold(f64::NEG_INFINITY, f64::max);
                if !hs.is_finite() { return not_here("the report run has no specular rows") }
                let s = [save(0), save(1)];
                let (verdict, why) = speed_verdict(1.0 / 0.8, s.map(|x| 1.0 / (1.0 - x)));
                Answer { v6m: format!("saves up to {}", pct(s[0])), m4: format!("saves up to {}", pct(s[1])), host: format!("saves up to {}", pct(hs)), verdict,
                    why: format!("whole Phong frames on the sphere, best n: {why}"), error: String::new() } } },
        Claim { id: "cq-hw", section: "002 §3.1", text: "the device takes 2 ROMs, 2 adders, 5 registers, 5 multipliers", seed: "2/2/5/5",
            answer: |_| not_here("hardware units") },
        Claim { id: "energy-n17", section: "002 §2.5", text: "un-normalised cosine-quadratic is not energy-correct for n ∈ [1, 17]", seed: "n ≤ 17",
            answer: |_| not_here("a reflectance integral: docs/specular.md, energy table") },
        Claim { id: "energy-norm", section: "002 §2.5 (2.26)", text: "the factor (n + 6)/24.55 keeps the reflectance ≤ 1 for n ∈ [1, 1000]", seed: "R ≤ 1",
            answer: |_| not_here("a reflectance integral: docs/specular.md, energy table") },
        Claim { id: "sa-1-7", section: "002 §2.4 (2.19)", text: "1/7 ≈ 1/8 + 1/64 gives ΔI = 35.8594 for 36.4286", seed: "0.5692 (1.56 %)",
            answer: |_| not_here("one division, reproduced by a unit test of `fixshade::divide`") },
        Claim { id: "sa-8-err", section: "002 §2.4 fig. 2.12", text: "8 shifts: largest absolute error 0.4427, mean relative error 0.81 %", seed: "0.4427, 0.81 %",
            answer: |_| not_here("errors of single divisions, tested in `fixshade::divide`; the divide rows give the image error") },
        Claim { id: "gouraud-ops-100", section: "002 §2.4 table 2.1", text: "a 100-pixel triangle takes 408 additions and 42 divisions", seed: "408 ±, 42 ÷",
            answer: |_| not_here("operations are not counted; instructions per pixel are") },
        Claim { id: "sa-1.43x", section: "002 §2.4", text: "shift-and-add makes Gouraud 1.43× faster than with a divide instruction", seed: "1.43×",
            answer: |ctx| {
                let d = |name: &'static str| of(ctx.rows, &move |c: &Config| c.kind == Kind::Divide && c.divide.name() == name);
                let sa = d("shift-add-8");
                if sa.is_empty() { return not_here("the report run has no divide rows") }
                speed(&sa, &span(ctx.rows, SpanName::CLASSIC), 1.43, "`classic` with `shift-add-8` against `exact`") } },
        Claim { id: "ray-k-2.3", section: "002 §2.6 (2.30)", text: "segments are interpolated when their ends differ by K ≤ 2.3", seed: "K = 2.3",
            answer: |_| not_here("ray casting has its own table: docs/raycast.md") },
        Claim { id: "ray-pe", section: "002 §2.6 (2.28)", text: "processing elements per row ⌈X/(L + 1) + 1⌉", seed: "⌈X/(L+1)+1⌉",
            answer: |_| not_here("ray casting has its own table: docs/raycast.md") },
        Claim { id: "nmse-scale", section: "002 §3.4 (3.1)", text: "NMSE ≤ 1e-4 is indistinguishable, ≤ 2.5e-4 minor, ≤ 1e-3 noticeable", seed: "1e-4 / 2.5e-4 / 1e-3",
            answer: |_| not_here("the report's verdict column uses this scale; perception is not measured") },
    ]
}

/// Counts of each verdict, as one sentence.
pub fn tally(rows: &[Row], inputs: &Inputs) -> String {
    let ctx = Ctx { rows, inputs };
    let all: Vec<Verdict> = claims().iter().map(|c| (c.answer)(&ctx).verdict).collect();
    let n = |v: Verdict| all.iter().filter(|x| **x == v).count();
    format!(
        "Of the seeds' {} quantitative claims, {} hold, {} hold in part, {} do not, and {} are \
         not measured here.",
        all.len(),
        n(Verdict::Holds),
        n(Verdict::InPart),
        n(Verdict::DoesNotHold),
        n(Verdict::NotMeasured)
    )
}

/// The claims table in markdown.
pub fn markdown(rows: &[Row], inputs: &Inputs) -> String {
    let ctx = Ctx { rows, inputs };
    let mut m = String::new();
    let _ = writeln!(
        m,
        "| id | seed § | claim | seed | ours: error | ours: {} instr | ours: {} instr | ours: host | verdict | why |",
        BOARDS[0].1, BOARDS[1].1
    );
    let _ = writeln!(m, "|---|---|---|---|---|---|---|---|---|---|");
    let dash = |s: String| if s.is_empty() { "—".to_string() } else { s };
    for c in claims() {
        let a = (c.answer)(&ctx);
        let _ = writeln!(
            m,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            c.id,
            c.section,
            c.text,
            c.seed,
            dash(a.error),
            dash(a.v6m),
            dash(a.m4),
            dash(a.host),
            a.verdict.as_str(),
            a.why
        );
    }
    let _ = writeln!(
        m,
        "\nSpeed verdicts come from the instruction counts (\"a vs b (×)\": the method's \
         instructions per pixel, its base's, and the speed-up); host figures are shown, \
         never decide. Specular error claims read docs/specular.csv; their instructions \
         per evaluation docs/mcu-specular.csv. Seed sections: 000 and 003 are the theses \
         on Gouraud and quadratic shading, 002 the one on reflectance models."
    );
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_and_every_claim_has_a_figure() {
        let c = claims();
        assert_eq!(c.len(), 41);
        for (i, a) in c.iter().enumerate() {
            assert!(!a.seed.is_empty() && !a.section.is_empty(), "{}", a.id);
            assert!(c[i + 1..].iter().all(|b| b.id != a.id), "{}", a.id);
        }
    }

    #[test]
    fn speed_verdicts() {
        assert_eq!(speed_verdict(2.0, [1.9, 2.5]).0, Verdict::Holds);
        assert_eq!(speed_verdict(2.0, [1.5, 2.5]).0, Verdict::InPart);
        assert_eq!(speed_verdict(2.0, [1.2, 1.1]).0, Verdict::InPart);
        assert_eq!(speed_verdict(2.0, [1.0, 0.8]).0, Verdict::DoesNotHold);
    }

    #[test]
    fn spec_bounds_and_missing_rows() {
        let inputs = Inputs {
            spec: vec![SpecRow {
                model: "schlick".into(),
                n: 8,
                max_abs: 0.1,
                abs_epi: 0.01,
                rel_epi: 0.05,
                rel_decay: 0.2,
                nmse: [1e-5, 2e-5],
                ns_per_eval: 1.0,
            }],
            mcu_spec: HashMap::new(),
        };
        let ctx = Ctx {
            rows: &[],
            inputs: &inputs,
        };
        let a = spec_bound(&ctx, "schlick", 0.032, |r| r.rel_epi, "x", true);
        assert_eq!(a.verdict, Verdict::DoesNotHold);
        assert_eq!(a.error, "5.00 % (n = 8)");
        assert_eq!(
            spec_bound(&ctx, "quadratic", 0.02, |r| r.rel_epi, "x", true).verdict,
            Verdict::NotMeasured
        );
        // No rows: a speed claim says so instead of a number.
        let counter = claims().into_iter().find(|c| c.id == "counter-2x").unwrap();
        assert_eq!((counter.answer)(&ctx).verdict, Verdict::NotMeasured);
    }
}
