//! The HTML pieces of a report: escaping, base64 for inline images, tables, figures and the
//! stylesheet. Pure string building.

/// `text` with `&`, `<`, `>` and `"` escaped for HTML text and attribute values, and control
/// characters (not allowed in HTML: a file name or a log's field can hold ESC) written as
/// `\u{1b}`, as on the terminal; newline and tab are kept.
pub(super) fn esc(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\n' | '\t' => out.push(c),
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", u32::from(c))),
            c => out.push(c),
        }
    }
    out
}

/// Escaped text with every `` `code` `` span set as `<code>`.
pub(super) fn esc_code(text: &str) -> String {
    let mut out = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            out.push_str("<code>");
            out.push_str(&esc(part));
            out.push_str("</code>");
        } else {
            out.push_str(&esc(part));
        }
    }
    out
}

/// Standard base64 (RFC 4648, with padding).
pub(super) fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A table: a header row and body rows of already-escaped HTML cells; columns whose body
/// cells all read as numbers are right-aligned.
pub(super) fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let numeric: Vec<bool> = (0..header.len())
        .map(|k| {
            k > 0
                && rows.iter().all(|r| {
                    r.get(k).is_none_or(|c| {
                        let c = c.trim().trim_start_matches(['+', '-', '−', '±', '→', ' ']);
                        c.is_empty() || c == "—" || c.starts_with(|ch: char| ch.is_ascii_digit())
                    })
                })
        })
        .collect();
    let class = |k: usize| if numeric[k] { " class=\"num\"" } else { "" };
    let mut out = String::from("<table>\n<thead><tr>");
    for (k, h) in header.iter().enumerate() {
        out.push_str(&format!("<th{}>{}</th>", class(k), esc(h)));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for r in rows {
        out.push_str("<tr>");
        for (k, c) in r.iter().enumerate() {
            let cls = if k < numeric.len() { class(k) } else { "" };
            out.push_str(&format!("<td{cls}>{c}</td>"));
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody>\n</table>\n");
    out
}

/// A figure: an inline image (`mime`, bytes) with alt text and a caption (escaped here).
pub(super) fn figure(id: &str, mime: &str, bytes: &[u8], alt: &str, caption: &str) -> String {
    format!(
        "<figure id=\"{}\">\n<img src=\"data:{mime};base64,{}\" alt=\"{}\">\n\
         <figcaption>{}</figcaption>\n</figure>\n",
        esc(id),
        base64(bytes),
        esc(alt),
        esc_code(caption)
    )
}

/// The page's stylesheet: readable type, quiet tables, figures that fit the page.
pub(super) const STYLE: &str = "\
body { font-family: system-ui, -apple-system, 'Segoe UI', 'DejaVu Sans', sans-serif;
       color: #1a1a1a; background: #fff; margin: 0; line-height: 1.45; }
main { max-width: 1120px; margin: 0 auto; padding: 24px 32px 48px; }
h1 { font-size: 1.6em; margin: 0.2em 0 0.1em; }
h2 { font-size: 1.2em; margin: 1.6em 0 0.5em; border-bottom: 1px solid #ddd;
     padding-bottom: 0.2em; }
p.meta { color: #555; margin: 0.2em 0; font-size: 0.95em; }
code { font-family: 'DejaVu Sans Mono', Menlo, Consolas, monospace; font-size: 0.92em;
       background: #f3f3f3; padding: 0 0.25em; border-radius: 3px; }
.verdict { border-left: 6px solid #2c7fb8; background: #eef5fb; padding: 12px 18px;
           margin: 18px 0; font-size: 1.1em; }
.verdict.found { border-color: #2ca02c; background: #eef8ee; }
.verdict.unexplained { border-color: #d62728; background: #fbeeee; }
.verdict p { margin: 0.3em 0; }
.verdict .detail { font-size: 0.85em; color: #444; }
table { border-collapse: collapse; margin: 0.5em 0 1em; font-size: 0.92em; }
th, td { padding: 4px 12px; border-bottom: 1px solid #e4e4e4; text-align: left;
         vertical-align: top; }
th { background: #f6f6f6; font-weight: 600; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
.tables { display: flex; flex-wrap: wrap; gap: 8px 40px; align-items: flex-start; }
p.note { color: #555; font-size: 0.88em; margin-top: -0.4em; }
figure { margin: 1em 0 1.6em; }
figure img { max-width: 100%; height: auto; border: 1px solid #e4e4e4; }
figcaption { color: #444; font-size: 0.9em; margin-top: 0.3em; }
ol.next li, ul.notes li { margin: 0.3em 0; }
footer { color: #777; font-size: 0.85em; margin-top: 2em; }
";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_rfc_vectors() {
        for (raw, enc) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), enc);
        }
    }

    #[test]
    fn escaping_and_code_spans() {
        assert_eq!(esc("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
        // Control bytes (a title from a file name) are shown, never passed into the page.
        assert_eq!(esc("f\u{1b}]0;x\u{7}.csv\n"), "f\\u{1b}]0;x\\u{7}.csv\n");
        assert_eq!(esc_code("`c_m_q` <x>"), "<code>c_m_q</code> &lt;x&gt;");
    }
}
