//! The report as documents: Markdown, one self-contained HTML page, JSON.

use std::path::Path;

use super::PublicationReport;
use crate::Error;

impl PublicationReport {
    /// The report as Markdown.
    pub fn markdown(&self) -> String {
        let p = &self.provenance;
        let mut s = format!(
            "# Audit of {}: **{}**\n\n## Result\n\n| | |\n|---|---|\n",
            p.result_file,
            self.verdict_stated()
        );
        for h in &self.headline {
            s += &format!("| {} | {} |\n", h.name, h.value.replace('|', "\\|"));
        }
        s += &format!(
            "| verdict | **{}** |\n\n## Provenance\n\n| | |\n|---|---|\n",
            self.verdict_stated()
        );
        let mut row = |k: &str, v: String| s += &format!("| {k} | {} |\n", v.replace('|', "\\|"));
        row("result file SHA-256", format!("`{}`", p.sha256));
        row("kind", p.kind.clone());
        if let Some(m) = &p.recorded {
            row("recorded by", format!("lorentz {}", m.version));
            row(
                "engine",
                format!(
                    "{}{}",
                    m.engine,
                    m.simd.as_ref().map_or(String::new(), |s| format!(" ({s})"))
                ),
            );
            row("precision", m.precision.clone());
            row("seed", m.seed.map_or("-".into(), |x| x.to_string()));
            row("threads", m.threads.map_or("-".into(), |x| x.to_string()));
            row(
                "recorded command line (shown, never run)",
                m.command_line.join(" ").replace(['\n', '\r', '`'], " "),
            );
        }
        row(
            "report by",
            format!("lorentz {} (git {}), {}", p.version, p.git_commit, p.rustc),
        );
        row("CPU", p.cpu.clone());
        row("date (UTC)", p.date_utc.clone());
        row(
            "settings",
            format!(
                "{}, {:.3e} collisions re-run, {:.1} s",
                if self.quick { "quick" } else { "full" },
                self.rerun_collisions as f64,
                self.seconds
            ),
        );
        s += "\n## Checks\n\n| | group | check | numbers |\n|---|---|---|---|\n";
        for c in &self.checks {
            s += &format!(
                "| **{}** | {} | {} | {} |\n",
                c.verdict,
                c.group,
                c.name,
                c.detail.replace('|', "\\|")
            );
        }
        for f in &self.figures {
            s += &format!("\n![{f}]({f}.png)\n");
        }
        s
    }

    /// The report as one self-contained HTML page (figures inlined as SVG from `dir`).
    pub fn html(&self, dir: &Path) -> String {
        let esc = crate::report::figures::html_escape;
        let p = &self.provenance;
        let mut s = format!(
            "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Audit of {}</title>\n<style>body{{font-family:sans-serif;max-width:70em;margin:2em auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:.3em .6em;vertical-align:top}}.PASS{{color:#060;font-weight:bold}}.FAIL{{color:#b00;font-weight:bold}}.SKIP{{color:#777;font-weight:bold}}.INCOMPLETE{{color:#b60;font-weight:bold}}</style></head><body>\n<h1>Audit of {}: <span class=\"{}\">{}</span></h1>\n<h2>Result</h2><table>\n",
            esc(&p.result_file),
            esc(&p.result_file),
            self.verdict,
            self.verdict
        );
        for h in &self.headline {
            s += &format!(
                "<tr><th>{}</th><td>{}</td></tr>\n",
                esc(&h.name),
                esc(&h.value)
            );
        }
        s += &format!(
            "<tr><th>verdict</th><td class=\"{}\">{}</td></tr>\n</table>\n<h2>Provenance</h2><table>\n",
            self.verdict,
            esc(&self.verdict_stated())
        );
        let mut row =
            |k: &str, v: &str| s += &format!("<tr><th>{k}</th><td>{}</td></tr>\n", esc(v));
        row("result file SHA-256", &p.sha256);
        row("kind", &p.kind);
        if let Some(m) = &p.recorded {
            row("recorded by", &format!("lorentz {}", m.version));
            row(
                "engine",
                &format!(
                    "{}{}",
                    m.engine,
                    m.simd.as_ref().map_or(String::new(), |s| format!(" ({s})"))
                ),
            );
            row("precision", &m.precision);
            row("seed", &m.seed.map_or("-".into(), |x| x.to_string()));
            row(
                "recorded command line (shown, never run)",
                &m.command_line.join(" "),
            );
        }
        row(
            "report by",
            &format!("lorentz {} (git {}), {}", p.version, p.git_commit, p.rustc),
        );
        row("CPU", &p.cpu);
        row("date (UTC)", &p.date_utc);
        s += "</table>\n<h2>Checks</h2><table><tr><th></th><th>group</th><th>check</th><th>numbers</th></tr>\n";
        for c in &self.checks {
            s += &format!(
                "<tr><td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                c.verdict,
                c.verdict,
                esc(&c.group),
                esc(&c.name),
                esc(&c.detail)
            );
        }
        s += "</table>\n";
        for f in &self.figures {
            let svg = crate::files::read_to_string(
                dir.join(format!("{f}.svg")),
                crate::files::Cap::DOCUMENT,
            )
            .unwrap_or_default();
            let svg = svg.trim_start_matches(|c| c != '<');
            let svg = svg
                .strip_prefix("<?xml")
                .map_or(svg, |r| r.split_once("?>").map_or(r, |x| x.1));
            s += &format!("<h2>{}</h2>\n{}\n", esc(f), svg);
        }
        s += "</body></html>\n";
        s
    }

    /// Writes `report.md`, `report.html` and `report.json` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        let json = serde_json::to_string_pretty(self).map_err(Error::encode)?;
        for (name, text) in [
            ("report.md", self.markdown()),
            ("report.html", self.html(dir)),
            ("report.json", json),
        ] {
            let path = dir.join(name);
            crate::files::write(&path, text)?;
        }
        Ok(())
    }
}
