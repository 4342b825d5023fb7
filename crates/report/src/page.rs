//! A self-contained HTML page: a heading, a few paragraphs, a table, and figures
//! (each PNG shown, linking to its SVG), to open from the run directory.

use std::fmt::Write as _;
use std::path::Path;

use crate::{ReportError, write_atomic};

/// A page's content.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Page {
    /// The heading and window title.
    pub title: String,
    /// Paragraphs under the heading (plain text).
    pub paragraphs: Vec<String>,
    /// The table's header cells.
    pub header: Vec<String>,
    /// The table's rows.
    pub rows: Vec<Vec<String>>,
    /// Figures: file stem (`<stem>.png` and `<stem>.svg` beside the page) and caption.
    pub figures: Vec<(String, String)>,
}

/// `text` with HTML's special characters escaped.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

impl Page {
    /// The page as HTML.
    pub fn html(&self) -> String {
        let mut h = String::new();
        let title = escape(&self.title);
        // Writing to a String cannot fail.
        let _ = write!(
            h,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{title}</title>\n<style>\n\
             body {{ font-family: sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em; color: #222; }}\n\
             table {{ border-collapse: collapse; margin: 1em 0; }}\n\
             th, td {{ border: 1px solid #bbb; padding: 0.35em 0.8em; text-align: right; }}\n\
             th:first-child, td:first-child {{ text-align: left; }}\n\
             th {{ background: #eee; }}\n\
             .figures {{ display: flex; flex-wrap: wrap; gap: 1em; }}\n\
             figure {{ margin: 0; width: 520px; }}\n\
             figure img {{ width: 100%; border: 1px solid #ddd; }}\n\
             </style>\n</head>\n<body>\n<h1>{title}</h1>\n"
        );
        for p in &self.paragraphs {
            let _ = writeln!(h, "<p>{}</p>", escape(p));
        }
        if !self.header.is_empty() {
            h.push_str("<table>\n<tr>");
            for c in &self.header {
                let _ = write!(h, "<th>{}</th>", escape(c));
            }
            h.push_str("</tr>\n");
            for row in &self.rows {
                h.push_str("<tr>");
                for c in row {
                    let _ = write!(h, "<td>{}</td>", escape(c));
                }
                h.push_str("</tr>\n");
            }
            h.push_str("</table>\n");
        }
        h.push_str("<div class=\"figures\">\n");
        for (stem, caption) in &self.figures {
            let stem = escape(stem);
            let _ = writeln!(
                h,
                "<figure><a href=\"{stem}.svg\"><img src=\"{stem}.png\" alt=\"{stem}\"></a>\
                 <figcaption>{}</figcaption></figure>",
                escape(caption)
            );
        }
        h.push_str("</div>\n</body>\n</html>\n");
        h
    }

    /// Writes the page to `path`, whole or not at all.
    pub fn write(&self, path: &Path) -> Result<(), ReportError> {
        write_atomic(path, self.html().as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_figures_link_their_svg() {
        let page = Page {
            title: "a < b & c".into(),
            paragraphs: vec!["\"quoted\"".into()],
            header: vec!["k".into(), "v".into()],
            rows: vec![vec!["<x>".into(), "1".into()]],
            figures: vec![("fig8".into(), "errors > 0".into())],
        };
        let h = page.html();
        assert!(h.contains("<title>a &lt; b &amp; c</title>"));
        assert!(h.contains("<p>&quot;quoted&quot;</p>"));
        assert!(h.contains("<td>&lt;x&gt;</td>"));
        assert!(h.contains("<a href=\"fig8.svg\"><img src=\"fig8.png\""));
        assert!(h.contains("errors &gt; 0"));
        assert!(!h.contains("<x>"));
    }
}
