//! JUnit XML, the report format CI servers display: one `<testsuite>` of
//! `<testcase>`s, each passed or carrying one `<failure>`.

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
    /// Figures worth keeping with the report (printed as `<system-out>`).
    pub output: String,
}

pub fn render(suite: &str, cases: &[TestCase]) -> String {
    let failures = cases.iter().filter(|c| c.failure.is_some()).count();
    let time: f64 = cases.iter().map(|c| c.time_s).sum();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        xml,
        "<testsuites><testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" time=\"{time:.3}\">",
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
        if let Some(reason) = &case.failure {
            let first = reason.lines().next().unwrap_or_default();
            let _ = write!(
                xml,
                "<failure message=\"{}\">{}</failure>",
                escape(first),
                escape(reason)
            );
        }
        if !case.output.is_empty() {
            let _ = write!(xml, "<system-out>{}</system-out>", escape(&case.output));
        }
        xml.push_str("</testcase>\n");
    }
    xml.push_str("</testsuite></testsuites>\n");
    xml
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
                output: String::new(),
            },
            TestCase {
                classname: "a&b".into(),
                name: "phong".into(),
                time_s: 0.25,
                failure: Some("max error 0.2 > 0.001 <interior>\nsecond line".into()),
                output: "fig \"1\"".into(),
            },
        ];
        let xml = render("shadelab check", &cases);
        assert!(xml.contains("tests=\"2\" failures=\"1\""));
        assert!(xml.contains("classname=\"a&amp;b\""));
        assert!(xml.contains("<failure message=\"max error 0.2 &gt; 0.001 &lt;interior&gt;\">"));
        assert!(xml.contains("<system-out>fig &quot;1&quot;</system-out>"));
        assert_eq!(xml.matches("<testcase").count(), 2);
        assert_eq!(xml.matches("</testcase>").count(), 2);
    }
}
