//! Measurements from the host benchmarks (`blender-bench`, `meshlab-bench`) as a table of
//! times and ratios.
//!
//! A measurement is one variant (`katachi`, `host`, `floor`, …) of one case in one round.
//! Ratios are taken per round (katachi's time over the other variant's in the same round,
//! so a busy moment of the shared machine weighs on both) and summarized by their median
//! and range; times by their median and range.

use std::collections::BTreeMap;
use std::fmt::Write as _;

/// One timed run.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// The host, e.g. `Blender 3.4.1`.
    pub host: String,
    pub case: String,
    pub variant: String,
    pub round: u32,
    pub seconds: f64,
}

/// A ratio the issue asks for: katachi's time / the `against` variant's (`host` or `floor`)
/// ≤ `limit`, for the cases whose name starts with `case`, on the hosts whose name starts
/// with `host` (empty: all).
pub struct Goal {
    pub case: &'static str,
    pub host: &'static str,
    pub against: &'static str,
    pub limit: f64,
}

/// Parses the `BENCH\thost\tcase\tvariant\tround\tseconds\tnotes` lines of a bench script's
/// output (other lines are ignored); `host_prefix` is put before the host field.
pub fn parse(output: &str, host_prefix: &str) -> Result<Vec<Sample>, String> {
    let mut out = Vec::new();
    for line in output.lines() {
        let Some(rest) = line.strip_prefix("BENCH\t") else {
            continue;
        };
        let f: Vec<&str> = rest.split('\t').collect();
        if f.len() < 5 {
            return Err(format!("a malformed bench line: {line:?}"));
        }
        let bad = |what: &str| format!("a bench line with a bad {what}: {line:?}");
        out.push(Sample {
            host: format!("{host_prefix}{}", f[0]),
            case: f[1].to_string(),
            variant: f[2].to_string(),
            round: f[3].parse().map_err(|_| bad("round"))?,
            seconds: f[4].parse().map_err(|_| bad("time"))?,
        });
    }
    Ok(out)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// `median (min–max)` of `v`, each formatted by `f`.
fn spread(mut v: Vec<f64>, f: impl Fn(f64) -> String) -> String {
    if v.is_empty() {
        return "–".into();
    }
    let m = median(&mut v);
    format!("{} ({}–{})", f(m), f(v[0]), f(v[v.len() - 1]))
}

fn seconds(s: f64) -> String {
    if s < 1.0 {
        format!("{:.0} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

fn ratio(r: f64) -> String {
    format!("{r:.2}×")
}

/// Per-round ratios `variant / against` in one (host, case).
fn ratios(samples: &[&Sample], variant: &str, against: &str) -> Vec<f64> {
    let by_round = |v: &str| -> BTreeMap<u32, f64> {
        samples
            .iter()
            .filter(|s| s.variant == v)
            .map(|s| (s.round, s.seconds))
            .collect()
    };
    let (a, b) = (by_round(variant), by_round(against));
    a.iter()
        .filter_map(|(r, x)| b.get(r).map(|y| x / y))
        .collect()
}

/// The table: one row per (host, case, katachi variant), with the times of that variant,
/// the host's own tool (`host`) and the floor (`floor`), katachi's per-round ratios to both,
/// and whether each goal is met: by every round, by the median only, or not.
pub fn table(samples: &[Sample], goals: &[Goal]) -> String {
    let mut groups: BTreeMap<(String, String), Vec<&Sample>> = BTreeMap::new();
    for s in samples {
        groups
            .entry((s.host.clone(), s.case.clone()))
            .or_default()
            .push(s);
    }
    let mut out = String::new();
    out.push_str(
        "| host | case | operation | katachi | host's tool | floor | katachi / host's tool | katachi / floor | goals |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    let times = |group: &[&Sample], v: &str| -> Vec<f64> {
        group
            .iter()
            .filter(|s| s.variant == v)
            .map(|s| s.seconds)
            .collect()
    };
    for ((host, case), group) in &groups {
        let mut variants: Vec<&str> = Vec::new();
        for s in group.iter().filter(|s| s.variant.starts_with("katachi")) {
            if !variants.contains(&s.variant.as_str()) {
                variants.push(&s.variant);
            }
        }
        for v in variants {
            let mut verdicts = Vec::new();
            let mut cells = Vec::new();
            for against in ["host", "floor"] {
                let rs = ratios(group, v, against);
                for g in goals.iter().filter(|g| {
                    case.starts_with(g.case) && host.starts_with(g.host) && g.against == against
                }) {
                    if rs.is_empty() {
                        continue;
                    }
                    let worst = rs.iter().copied().fold(f64::NAN, f64::max);
                    let med = median(&mut rs.clone());
                    let verdict = if worst <= g.limit {
                        "met"
                    } else if med <= g.limit {
                        "met by the median"
                    } else {
                        "not met"
                    };
                    verdicts.push(format!("/ {against} ≤ {}×: {verdict}", g.limit));
                }
                cells.push(spread(rs, ratio));
            }
            let _ = writeln!(
                out,
                "| {host} | {case} | {v} | {} | {} | {} | {} | {} | {} |",
                spread(times(group, v), seconds),
                spread(times(group, "host"), seconds),
                spread(times(group, "floor"), seconds),
                cells[0],
                cells[1],
                verdicts.join("; ")
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(variant: &str, round: u32, seconds: f64) -> Sample {
        Sample {
            host: "Blender 3.4.1".into(),
            case: "subdivide".into(),
            variant: variant.into(),
            round,
            seconds,
        }
    }

    #[test]
    fn parses_bench_lines_and_skips_others() {
        let out =
            "katachi blender bench\nBENCH\t3.4.1\tcut 330k\tfloor\t2\t0.125000\tload=1.2\nok\n";
        let v = parse(out, "Blender ").unwrap();
        assert_eq!(v.len(), 1);
        assert_eq!(v[0].host, "Blender 3.4.1");
        assert_eq!(v[0].case, "cut 330k");
        assert_eq!(v[0].round, 2);
        assert_eq!(v[0].seconds, 0.125);
        assert!(parse("BENCH\t3.4\tx\ty\tz\t1.0\t", "").is_err());
    }

    #[test]
    fn ratios_are_per_round_and_goals_judged_by_the_worst_round() {
        let samples = vec![
            s("katachi", 0, 1.0),
            s("host", 0, 4.0),
            s("katachi", 1, 3.0),
            s("host", 1, 4.0),
            s("katachi", 2, 1.0),
            s("host", 2, 5.0),
        ];
        let goals = [Goal {
            case: "subdivide",
            host: "",
            against: "host",
            limit: 0.5,
        }];
        let t = table(&samples, &goals);
        // Ratios 0.25, 0.75, 0.2: median 0.25, worst 0.75.
        assert!(t.contains("0.25× (0.20×–0.75×)"), "{t}");
        assert!(t.contains("met by the median"), "{t}");
        assert!(t.contains("1.00 s (1.00 s–3.00 s)"), "{t}");
    }
}
