//! JUnit XML, the report format CI servers display: one `<testsuite>` of
//! `<testcase>`s, each passed, or carrying one `<failure>` (it ran and
//! missed its thresholds) or one `<error>` (it could not run).

use std::fmt::Write as _;

use crate::markup::escape;

pub struct TestCase {
    /// Shown as the test's class (here: the scene).
    pub classname: String,
    /// Shown as the test's name (here: the shading mode).
    pub name: String,
    pub time_s: f64,
    /// `None` when the case passed; else the reason, one line per failed figure.
    pub failure: Option<String>,
    /// Why the case could not run (a scene that does not load, no device,
    /// a hook that does not compile); such a case has no `failure`.
    pub error: Option<String>,
    /// Figures worth keeping with the report (printed as `<system-out>`).
    pub output: String,
}

impl TestCase {
    /// The case as a shard's record keeps it (`golden --merge` and
    /// `check --merge` join shards' cases into one report), and back.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "classname": self.classname,
            "name": self.name,
            "time_s": self.time_s,
            "failure": self.failure,
            "error": self.error,
            "output": self.output,
        })
    }

    /// The case from `to_json`'s record; what is missing is empty.
    pub fn from_json(v: &serde_json::Value) -> TestCase {
        let text = |k: &str| v.get(k).and_then(|x| x.as_str()).map(str::to_string);
        TestCase {
            classname: text("classname").unwrap_or_default(),
            name: text("name").unwrap_or_default(),
            time_s: v.get("time_s").and_then(|x| x.as_f64()).unwrap_or(0.0),
            failure: text("failure"),
            error: text("error"),
            output: text("output").unwrap_or_default(),
        }
    }
}

pub fn render(suite: &str, cases: &[TestCase]) -> String {
    let failures = cases.iter().filter(|c| c.failure.is_some()).count();
    let errors = cases.iter().filter(|c| c.error.is_some()).count();
    let time: f64 = cases.iter().map(|c| c.time_s).sum();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        xml,
        "<testsuites><testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\" time=\"{time:.3}\">",
        escape(suite),
        cases.len()
    );
    for case in cases {
        let _ = write!(
            xml,
            "  <testcase classname=\"{}\" name=\"{}\" time=\"{:.3}\">",
            escape(&case.classname),
            escape(&case.name),
            case.time_s
        );
        for (tag, reason) in [("error", &case.error), ("failure", &case.failure)] {
            if let Some(reason) = reason {
                let _ = write!(
                    xml,
                    "<{tag} message=\"{}\">{}</{tag}>",
                    escape(&one_line(reason)),
                    escape(reason)
                );
            }
        }
        if !case.output.is_empty() {
            let _ = write!(xml, "<system-out>{}</system-out>", escape(&case.output));
        }
        xml.push_str("</testcase>\n");
    }
    xml.push_str("</testsuite></testsuites>\n");
    xml
}

/// The reason as one attribute value: its lines joined, so that a compiler's
/// message after "does not compile:" is not cut off; at most 2000
/// characters (the whole text is the element's body).
fn one_line(reason: &str) -> String {
    let joined = reason
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" | ");
    if joined.chars().count() > 2000 {
        joined.chars().take(1999).chain(['…']).collect()
    } else {
        joined
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_failures_and_escapes_text() {
        let cases = [
            TestCase {
                classname: "a&b".into(),
                name: "flat".into(),
                time_s: 0.5,
                failure: None,
                error: None,
                output: String::new(),
            },
            TestCase {
                classname: "a&b".into(),
                name: "phong".into(),
                time_s: 0.25,
                failure: Some("max error 0.2 > 0.001 <interior>\nsecond line".into()),
                error: None,
                output: "fig \"1\"".into(),
            },
            TestCase {
                classname: "b".into(),
                name: "phong".into(),
                time_s: 0.0,
                failure: None,
                error: Some(
                    "lighting hook h.glsl does not compile:\nh.glsl:2: 'x' : undeclared".into(),
                ),
                output: String::new(),
            },
        ];
        let xml = render("shadelab check", &cases);
        assert!(xml.contains("tests=\"3\" failures=\"1\" errors=\"1\""));
        assert!(xml.contains("classname=\"a&amp;b\""));
        assert!(xml.contains(
            "<failure message=\"max error 0.2 &gt; 0.001 &lt;interior&gt; | second line\">"
        ));
        // The compiler's words are in the message, not cut at the colon.
        assert!(xml.contains(
            "<error message=\"lighting hook h.glsl does not compile: | h.glsl:2: &#39;x&#39; : undeclared\">"
        ));
        assert!(xml.contains("<system-out>fig &quot;1&quot;</system-out>"));
        assert_eq!(xml.matches("<testcase").count(), 3);
        assert_eq!(xml.matches("</testcase>").count(), 3);
    }
}
