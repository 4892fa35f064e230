//! The throughput table: one row per measurement, written to and read from
//! `reports/throughput.csv` with the `csv` crate (quoting, a fixed header), so any CSV reader
//! gets the same figures as `tridist advise`.

use std::path::Path;

use tridist::PathCounts;

/// The CSV header, in order.
pub const HEADER: [&str; 19] = [
    "workload",
    "query",
    "implementation",
    "precision",
    "threads",
    "tolerance",
    "outputs",
    "stages",
    "queries_per_second",
    "pairs",
    "prefiltered",
    "delegated",
    "refined",
    "recertified",
    "compacted",
    "widened",
    "exact",
    "uncertified",
    "undecided",
];

/// One throughput measurement: a kernel variant (implementation = variant name) or a peer
/// (implementation = `parry3d`, `fcl`) on a workload.
#[derive(Clone, Debug, PartialEq)]
pub struct TRow {
    /// Workload id ([`tridist_scenes::protocol::Named::id`]).
    pub workload: String,
    /// Query name (registry).
    pub query: String,
    /// Variant or peer.
    pub implementation: String,
    /// `f32` or `f64`.
    pub precision: String,
    /// Threads.
    pub threads: usize,
    /// Tolerance setting (`default`, `scaled:K`, `abs:X`, `exact`); `-` for peers.
    pub tolerance: String,
    /// What each query wrote: `answer` (squared distances only, or verdicts), or `points`
    /// (squared distances and closest points, as FCL's `TriangleDistance` always computes).
    pub outputs: String,
    /// Triangle distance's stages: `quick` (the default engine: the quick stage first), `full`
    /// (`Engine::quick_stage(false)`: every pair straight to the full fast stage); `-` for peers.
    pub stages: String,
    /// Queries per second (NaN when the result check failed).
    pub qps: f64,
    /// Path counts of one pass (zero for peers).
    pub counts: PathCounts,
}

/// The `outputs` value of a row that wrote the answer alone (squared distances or verdicts).
pub const ANSWER: &str = "answer";
/// The `outputs` value of a row that wrote closest points too.
pub const POINTS: &str = "points";

/// The `stages` value of a row measured on the default engine.
pub const QUICK: &str = "quick";
/// The `stages` value of a row measured without the quick stage.
pub const FULL: &str = "full";

impl TRow {
    /// Did the measurement write the answer alone (no closest points)?
    pub fn answer_only(&self) -> bool {
        self.outputs == ANSWER
    }

    /// Was it measured without the quick stage (`Engine::quick_stage(false)`)?
    pub fn full_stages(&self) -> bool {
        self.stages == FULL
    }

    /// The answer alone on the default engine: the row every table and `tridist advise`
    /// read unless they ask for closest points or for the stages.
    pub fn plain(&self) -> bool {
        self.answer_only() && !self.full_stages()
    }

    fn fields(&self) -> Vec<String> {
        let c = &self.counts;
        let mut v = vec![
            self.workload.clone(),
            self.query.clone(),
            self.implementation.clone(),
            self.precision.clone(),
            self.threads.to_string(),
            self.tolerance.clone(),
            self.outputs.clone(),
            self.stages.clone(),
            format!("{:.0}", self.qps),
        ];
        v.extend(
            [
                c.pairs,
                c.prefiltered,
                c.delegated,
                c.refined,
                c.recertified,
                c.compacted,
                c.widened,
                c.exact,
                c.uncertified,
                c.undecided,
            ]
            .map(|x| x.to_string()),
        );
        v
    }
}

/// Writes the rows with [`HEADER`].
///
/// # Errors
/// I/O errors, as a message naming the file.
pub fn write(path: &Path, rows: &[TRow]) -> Result<(), String> {
    let err = |e: csv::Error| format!("{}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(err)?;
    w.write_record(HEADER).map_err(err)?;
    for r in rows {
        w.write_record(r.fields()).map_err(err)?;
    }
    w.flush().map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads a file written by [`write`].
///
/// # Errors
/// A message with the file, line and field for an I/O error, a wrong header or a malformed row.
pub fn read(path: &Path) -> Result<Vec<TRow>, String> {
    let mut r = csv::Reader::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let h = r.headers().map_err(|e| format!("{}: {e}", path.display()))?.clone();
    // files written before the `undecided` column (the correctly rounded mode) read as 0 there
    let old = h.len() == HEADER.len() - 1 && h.iter().eq(HEADER[..HEADER.len() - 1].iter().copied());
    if h.iter().ne(HEADER) && !old {
        return Err(format!("{}: header is {:?}, expected {:?}", path.display(), h, HEADER));
    }
    let mut out = Vec::new();
    for (i, rec) in r.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| format!("{}: {e}", path.display()))?;
        let num = |k: usize| -> Result<u64, String> {
            rec[k]
                .parse()
                .map_err(|_| format!("{}:{line}: {} {:?} is not a count", path.display(), HEADER[k], &rec[k]))
        };
        // a rate that was measured: `advise` picks the largest, so NaN or 0 would mislead it
        let qps: f64 = rec[8].parse().ok().filter(|q: &f64| q.is_finite() && *q > 0.0).ok_or_else(|| {
            format!(
                "{}:{line}: queries_per_second {:?} is not a positive finite number",
                path.display(),
                &rec[8]
            )
        })?;
        if rec[3] != *"f32" && rec[3] != *"f64" {
            return Err(format!("{}:{line}: precision {:?} is neither f32 nor f64", path.display(), &rec[3]));
        }
        let threads = num(4)?;
        if threads == 0 {
            return Err(format!("{}:{line}: threads 0: at least 1", path.display()));
        }
        if ![QUICK, FULL, "-"].contains(&&rec[7]) {
            return Err(format!(
                "{}:{line}: stages {:?} is neither quick, full nor -",
                path.display(),
                &rec[7]
            ));
        }
        if rec[6] != *ANSWER && rec[6] != *POINTS {
            return Err(format!(
                "{}:{line}: outputs {:?} is neither answer nor points",
                path.display(),
                &rec[6]
            ));
        }
        out.push(TRow {
            workload: rec[0].to_string(),
            query: rec[1].to_string(),
            implementation: rec[2].to_string(),
            precision: rec[3].to_string(),
            threads: threads as usize,
            tolerance: rec[5].to_string(),
            outputs: rec[6].to_string(),
            stages: rec[7].to_string(),
            qps,
            counts: {
                // (`PathCounts` is non-exhaustive: built field by field)
                let mut c = PathCounts::default();
                c.pairs = num(9)?;
                c.prefiltered = num(10)?;
                c.delegated = num(11)?;
                c.refined = num(12)?;
                c.recertified = num(13)?;
                c.compacted = num(14)?;
                c.widened = num(15)?;
                c.exact = num(16)?;
                c.uncertified = num(17)?;
                c.undecided = if old { 0 } else { num(18)? };
                c
            },
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_including_commas_and_quotes() {
        let dir = std::env::temp_dir().join(format!("tridist-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.csv");
        let rows = vec![TRow {
            workload: "Fandisk vs \"Fandisk\", neighbouring".into(),
            query: "tri_tri".into(),
            implementation: "avx2fma".into(),
            precision: "f32".into(),
            threads: 2,
            tolerance: "default".into(),
            outputs: "points".into(),
            stages: "full".into(),
            qps: 12345.0,
            counts: {
                let mut c = PathCounts::default();
                (c.pairs, c.refined, c.compacted) = (10, 5, 3);
                c
            },
        }];
        write(&p, &rows).unwrap();
        assert_eq!(read(&p).unwrap(), rows);
        std::fs::write(&p, "a,b\n1,2\n").unwrap();
        assert!(read(&p).unwrap_err().contains("header"));
        let mut bad = std::fs::read_to_string(dir.join("t.csv")).unwrap_or_default();
        bad.clear();
        let head = HEADER.join(",");
        bad.push_str(&head);
        bad.push_str("\nw,q,i,f32,one,default,answer,quick,1,1,0,0,0,0,0,0,0,0,0\n");
        std::fs::write(&p, &bad).unwrap();
        let e = read(&p).unwrap_err();
        assert!(e.contains(":2: threads"), "{e}");
        std::fs::write(&p, format!("{head}\nw,q,i,f32,1,default,answer,slow,1,1,0,0,0,0,0,0,0,0,0\n"))
            .unwrap();
        let e = read(&p).unwrap_err();
        assert!(e.contains(":2: stages \"slow\""), "{e}");
        // values `advise` would have used silently: an unknown precision (its rows were never
        // matched, the rate printed "?"), a rate that is not a measurement (NaN was printed and
        // ranked), no threads
        let good = "w,q,i,f32,1,default,answer,quick,7,1,0,0,0,0,0,0,0,0,0";
        for (bad, says) in [
            (good.replace(",f32,", ",f33,"), ":3: precision \"f33\" is neither f32 nor f64"),
            (good.replace(",7,", ",NaN,"), ":3: queries_per_second \"NaN\" is not a positive finite number"),
            (good.replace(",7,", ",inf,"), ":3: queries_per_second \"inf\""),
            (good.replace(",7,", ",0,"), ":3: queries_per_second \"0\""),
            (good.replace(",7,", ",-7,"), ":3: queries_per_second \"-7\""),
            (good.replace("f32,1,", "f32,0,"), ":3: threads 0"),
        ] {
            std::fs::write(&p, format!("{head}\n{good}\n{bad}\n")).unwrap();
            let e = read(&p).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
        std::fs::write(&p, format!("{head}\n{good}\n")).unwrap();
        assert_eq!(read(&p).unwrap().len(), 1);
        // a file from before the `undecided` column reads as 0 undecided
        let (old_head, old_row) = (HEADER[..HEADER.len() - 1].join(","), good.rsplit_once(',').unwrap().0);
        std::fs::write(&p, format!("{old_head}\n{old_row}\n")).unwrap();
        assert_eq!(read(&p).unwrap()[0].counts.undecided, 0);
    }

    /// The committed file parses with the csv crate, every row has every field, and its
    /// figures are positive numbers.
    #[test]
    fn the_committed_csv_parses() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("throughput.csv");
        let rows = read(&p).unwrap();
        assert!(rows.len() > 100, "{} rows", rows.len());
        assert!(rows.iter().all(|r| r.qps > 0.0 && r.threads >= 1), "a row without a measurement");
        for q in tridist::Query::ALL {
            assert!(rows.iter().any(|r| r.query == q.name()), "{} never measured", q.name());
        }
        assert!(rows.iter().any(|r| r.implementation == "parry3d"));
        assert!(
            rows.iter().all(|r| r.outputs == "answer" || r.outputs == "points"),
            "an unknown outputs value"
        );
        assert!(
            rows.iter().any(|r| r.outputs == "points" && r.query == "tri_tri" && r.tolerance == "default"),
            "triangle distance with closest points never measured"
        );
        assert!(
            rows.iter().all(|r| ["quick", "full", "-"].contains(&r.stages.as_str())),
            "an unknown stages value"
        );
        assert!(
            rows.iter().any(|r| r.full_stages() && r.query == "tri_tri" && r.workload == "random"),
            "triangle distance without the quick stage never measured"
        );
    }
}
