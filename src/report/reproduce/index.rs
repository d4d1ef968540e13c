//! The reproduction's `index.html`: each step's tables, figures and data files.

use std::path::Path;

use super::ReproduceReport;

/// A Markdown pipe table as HTML (the only Markdown the index needs).
fn md_table_html(md: &str) -> String {
    let esc = crate::report::figures::html_escape;
    let mut s = String::from("<table>\n");
    let mut first = true;
    for line in md.lines().filter(|l| l.trim_start().starts_with('|')) {
        let cells: Vec<&str> = line
            .trim()
            .trim_matches('|')
            .split('|')
            .map(str::trim)
            .collect();
        if cells
            .iter()
            .all(|c| c.chars().all(|ch| ch == '-' || ch == ':'))
        {
            continue;
        }
        let tag = if first { "th" } else { "td" };
        first = false;
        s += "<tr>";
        for c in cells {
            s += &format!("<{tag}>{}</{tag}>", esc(c));
        }
        s += "</tr>\n";
    }
    s + "</table>\n"
}

pub(super) fn index_html(dir: &Path, r: &ReproduceReport) -> String {
    let mut s = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>lorentz reproduce ({})</title>\n<style>body{{font-family:sans-serif;max-width:75em;margin:2em auto}}table{{border-collapse:collapse;margin:1em 0}}td,th{{border:1px solid #ccc;padding:.25em .5em}}img{{max-width:48%;margin:.3em}}</style></head><body>\n<h1>Klages &amp; Dellago (2000), reproduced by lorentz {} — budget {}</h1>\n<p>seed {}, {}; every file in this folder was written by <code>lorentz reproduce</code>.</p>\n",
        r.budget.name(),
        env!("CARGO_PKG_VERSION"),
        r.budget.name(),
        r.meta.seed.unwrap_or(0),
        crate::report::counted(r.meta.threads.unwrap_or(0) as u64, "thread"),
    );
    for st in &r.steps {
        s += &format!(
            "<h2>{}</h2>\n<p><code>{}/</code>, {:.1} s{}</p>\n",
            st.title,
            st.name,
            st.seconds,
            if st.resumed {
                " (finished in an earlier run)"
            } else {
                ""
            }
        );
        for f in &st.files {
            if f.ends_with(".md")
                && let Ok(md) =
                    crate::files::read_to_string(dir.join(f), crate::files::Cap::DOCUMENT)
            {
                s += &md_table_html(&md);
            }
        }
        for f in st.files.iter().filter(|f| f.ends_with(".png")) {
            s += &format!("<a href=\"{f}\"><img src=\"{f}\" alt=\"{f}\"></a>\n");
        }
        let data: Vec<&String> = st
            .files
            .iter()
            .filter(|f| f.ends_with(".csv") || f.ends_with(".json"))
            .collect();
        if !data.is_empty() {
            s += "<p>data: ";
            for f in data {
                s += &format!("<a href=\"{f}\">{f}</a> ");
            }
            s += "</p>\n";
        }
    }
    s + "</body></html>\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_tables_become_html() {
        let h = md_table_html("| a | b<c |\n|---|---|\n| 1 | 2 |\n");
        assert_eq!(
            h,
            "<table>\n<tr><th>a</th><th>b&lt;c</th></tr>\n<tr><td>1</td><td>2</td></tr>\n</table>\n"
        );
    }
}
