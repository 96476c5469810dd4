//! The bench's output: the per-configuration table, the photon paths side by side, the CSV
//! rows and the scaling table (the JSON is the report's own serialisation).

use super::measure::{BenchResult, BufferDifference, Series};
use crate::passes::PhotonPath;
use serde::Serialize;
use std::fmt::Write as _;

#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub device: String,
    pub driver: String,
    pub results: Vec<BenchResult>,
}

impl BenchReport {
    /// The human-readable table: one row per configuration, per-pass medians, the total's
    /// median [p5–p95], the frame rate that total allows, and the paper's.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "device: {} ({})", self.device, self.driver);
        // The water's refraction and reflection columns only when some configuration has them.
        let surface = self.results.iter().any(|r| r.passes.iter().any(|p| p.pass == "refraction"));
        let ids: &[&str] = if surface {
            &["shadow", "refraction", "reflection", "scene", "caustics", "godrays", "filter", "compose"]
        } else {
            &["shadow", "scene", "caustics", "godrays", "filter", "compose"]
        };
        let _ = write!(out, "{:<32} {:>10}", "config", "photons");
        for id in ids {
            let _ = write!(out, " {:>10}", id);
        }
        let _ = writeln!(out, " {:>26} {:>9} {:>10}", "total ms median [p5–p95]", "GPU fps", "paper fps");
        for r in &self.results {
            let name = match r.photon_path {
                PhotonPath::GeometryShader => r.config.name.to_string(),
                PhotonPath::VertexOnly => format!("{} (vertex)", r.config.name),
                PhotonPath::Compute => format!("{} (compute)", r.config.name),
                PhotonPath::SplatFloor => format!("{} (splat floor)", r.config.name),
            };
            let _ = write!(out, "{:<32} {:>10}", name, r.caustic_photons + r.godray_photons);
            for id in ids {
                match r.passes.iter().find(|p| p.pass == *id) {
                    Some(p) => {
                        let _ = write!(out, " {:>10.2}", p.median_ms);
                    }
                    None => {
                        let _ = write!(out, " {:>10}", "-");
                    }
                }
            }
            let t = &r.total;
            let span = format!("{:.2} [{:.2}–{:.2}]", t.median_ms, t.p5_ms, t.p95_ms);
            let _ = writeln!(out, " {:>26} {:>9.1} {:>10}", span, 1000.0 / t.median_ms, r.config.paper_fps);
        }
        if self.results.iter().any(|r| r.photon_path != PhotonPath::GeometryShader) {
            out.push_str(&self.paths_table());
        }
        out.push_str(&self.memory_table());
        out.push_str(&self.counts_table());
        out
    }

    /// Each configuration's work per pass and shader stage (`--pipeline-statistics`).
    fn counts_table(&self) -> String {
        let mut out = String::new();
        for r in self.results.iter().filter(|r| !r.stage_counts.is_empty()) {
            let _ = writeln!(
                out,
                "\nwork per pass, last measured frame (pipeline statistics), {} ({}):\n{}",
                r.config.name,
                r.photon_path.name(),
                crate::vk::statistics::counts_table(r.stage_counts.iter().map(|c| (c.pass.as_str(), c.counts)))
            );
        }
        out
    }

    /// Device memory per configuration: the total and the peak of each run, then every target
    /// and buffer of the first run of each configuration (the other photon paths differ only
    /// in their own buffers, which their totals show).
    fn memory_table(&self) -> String {
        let mib = |bytes: u64| bytes as f64 / (1024.0 * 1024.0);
        let mut out = String::from(
            "
device memory (gpu-allocator's report; read-back buffers included):
",
        );
        for r in &self.results {
            let m = &r.memory;
            let _ = writeln!(
                out,
                "{:<32} {:>9.2} MiB in {:>3} allocations, peak {:>9.2} MiB",
                format!("{} ({})", r.config.name, r.photon_path.name()),
                mib(m.total_bytes),
                m.allocations.len(),
                mib(m.peak_bytes)
            );
        }
        let mut listed: Vec<&str> = Vec::new();
        for r in &self.results {
            if listed.contains(&r.config.name) {
                continue;
            }
            listed.push(r.config.name);
            let _ = writeln!(out, "{} ({}):", r.config.name, r.photon_path.name());
            for a in &r.memory.allocations {
                let _ = writeln!(out, "  {:<40} {:>10.3} MiB", a.name, mib(a.bytes));
            }
        }
        out
    }

    /// The photon paths side by side: each path's caustic and godray pass times, as a
    /// multiple of the geometry shader's, and how its buffers differ from the geometry
    /// shader's (relative L1, and the ratio of the sums).
    fn paths_table(&self) -> String {
        let mut out = String::from("\nphoton paths against the geometry shader (same configuration, same run):\n");
        let _ = writeln!(
            out,
            "{:<18} {:<18} {:>12} {:>8} {:>12} {:>8} {:>22} {:>22}",
            "config", "path", "caustics ms", "× GS", "godrays ms", "× GS", "caustic L1 (sum ×)", "godray L1 (sum ×)"
        );
        let ms = |r: &BenchResult, pass: &str| r.passes.iter().find(|p| p.pass == pass).map(|p| p.median_ms);
        for r in &self.results {
            let gs = self
                .results
                .iter()
                .find(|g| g.config.name == r.config.name && g.photon_path == PhotonPath::GeometryShader);
            let cell = |pass: &str| match (ms(r, pass), gs.and_then(|g| ms(g, pass))) {
                (Some(v), Some(g)) => (format!("{v:.2}"), format!("{:.2}", v / g)),
                (Some(v), None) => (format!("{v:.2}"), "-".into()),
                _ => ("-".into(), "-".into()),
            };
            let diff = |d: &Option<BufferDifference>| match d {
                Some(d) => format!("{:.2e} ({:.4})", d.relative_l1, d.sum_ratio),
                None if r.photon_path == PhotonPath::GeometryShader => "reference".into(),
                None => "-".into(),
            };
            let (c, cx) = cell("caustics");
            let (g, gx) = cell("godrays");
            let _ = writeln!(
                out,
                "{:<18} {:<18} {:>12} {:>8} {:>12} {:>8} {:>22} {:>22}",
                r.config.name,
                r.photon_path.name(),
                c,
                cx,
                g,
                gx,
                diff(&r.caustic_difference),
                diff(&r.godray_difference)
            );
        }
        out
    }

    /// One CSV row per configuration and pass (the total as pass "total").
    pub fn csv(&self) -> String {
        let mut out = String::from("device,driver,config,photon_path,scene,width,height,caustic_photons,godray_photons,frames,pass,median_ms,p5_ms,p95_ms,caustic_relative_l1,caustic_sum_ratio,godray_relative_l1,godray_sum_ratio\n");
        // Empty where there is no difference (the geometry shader's own rows).
        let diff = |d: &Option<BufferDifference>| match d {
            Some(d) => format!("{:.6e},{:.6}", d.relative_l1, d.sum_ratio),
            None => ",".to_string(),
        };
        for r in &self.results {
            for p in r.passes.iter().chain(std::iter::once(&r.total)) {
                let _ = writeln!(
                    out,
                    "\"{}\",\"{}\",{},{:?},{},{},{},{},{},{},{},{:.6},{:.6},{:.6},{},{}",
                    self.device,
                    self.driver,
                    r.config.name,
                    r.photon_path,
                    r.scene,
                    r.config.width,
                    r.config.height,
                    r.caustic_photons,
                    r.godray_photons,
                    r.frames,
                    p.pass,
                    p.median_ms,
                    p.p5_ms,
                    p.p95_ms,
                    diff(&r.caustic_difference),
                    diff(&r.godray_difference)
                );
            }
        }
        out
    }
}

/// The scaling table: each series' points and its fitted cost per unit.
pub fn scaling_table(series: &[Series]) -> String {
    let mut out = String::new();
    for s in series {
        let pts: Vec<String> = s.points.iter().map(|(x, y)| format!("{x:.3}→{y:.2}")).collect();
        let _ = writeln!(
            out,
            "{:<30} {:<9} {:>9.2} ms per unit (+{:.2} ms)   [{}]",
            s.parameter,
            s.pass,
            s.slope_ms,
            s.intercept_ms,
            pts.join(", ")
        );
    }
    out
}
