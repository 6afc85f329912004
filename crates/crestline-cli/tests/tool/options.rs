//! The tool's options are the library's: every option of every job's options
//! struct ([`crestline::jobs::defaults`], which the Python package reads too) is
//! an option of the command that runs the job, under the same name with dashes,
//! and the default the command's help shows is the library's.

use std::collections::BTreeMap;

use crestline::jobs::{defaults, Length};
use serde_json::Value;

use super::common::crestline;

/// Each job of [`defaults`] and the command that runs it.
const COMMANDS: [(&str, &str); 11] = [
    ("curvature", "curvature"),
    ("iso", "iso"),
    ("crest_lines", "crest-lines"),
    ("crease", "crease"),
    ("ridges", "ridges"),
    ("morse", "morse"),
    ("draw", "draw"),
    ("register", "register"),
    ("landmarks", "landmarks"),
    ("view", "view"),
    ("transfer", "transfer"),
];

/// The library's options a command leaves at their defaults on purpose:
/// registration's inner schedule is the library's to tune.
const LIBRARY_ONLY: [&str; 3] = ["coarse_iterations", "coarse_points", "tolerance"];

/// The help of each long option of `command`: its paragraph of `--help`.
fn options_help(command: &str) -> BTreeMap<String, String> {
    let out = crestline(&[command, "--help"]);
    assert!(out.status.success(), "{command} --help failed");
    let text = String::from_utf8(out.stdout).unwrap();
    let mut options = BTreeMap::new();
    let mut current: Option<(String, String)> = None;
    for line in text.lines() {
        let trimmed = line.trim_start();
        let flag = trimmed
            .strip_prefix("--")
            .or_else(|| trimmed.get(4..).and_then(|rest| rest.strip_prefix("--")));
        match flag {
            Some(rest) if trimmed.starts_with('-') => {
                options.extend(current.take());
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                    .collect();
                current = Some((name, line.to_string()));
            }
            _ if trimmed.is_empty() => options.extend(current.take()),
            _ => {
                if let Some((_, help)) = &mut current {
                    help.push(' ');
                    help.push_str(trimmed);
                }
            }
        }
    }
    options.extend(current);
    options
}

/// The value in `[default: X]` of an option's help, unquoted.
fn shown_default(help: &str) -> Option<String> {
    let start = help.find("[default: ")? + "[default: ".len();
    let end = start + help[start..].find(']')?;
    Some(help[start..end].trim_matches('"').to_string())
}

/// Whether `shown`, a default as the help prints it, is the library's `value`.
fn same_default(shown: &str, value: &Value) -> bool {
    match value {
        Value::Bool(b) => shown == b.to_string(),
        Value::Number(n) => shown.parse::<f64>().ok() == n.as_f64(),
        Value::String(s) => shown == s,
        // Numbers written `WxH`, `A,B` or `A B C`.
        Value::Array(items) => {
            let numbers: Vec<Option<f64>> = shown
                .split(['x', ',', ' '])
                .map(|n| n.parse().ok())
                .collect();
            numbers == items.iter().map(Value::as_f64).collect::<Vec<_>>()
        }
        // A length in scales or units.
        Value::Object(_) => shown
            .parse::<Length>()
            .is_ok_and(|length| serde_json::to_value(length).unwrap() == *value),
        _ => false,
    }
}

/// The options of `job`'s struct, with those of the structs it nests (a drawing's
/// ridges and Morse-Smale lines).
fn flattened(options: &Value) -> Vec<(String, Value)> {
    let mut all = Vec::new();
    for (name, value) in options.as_object().unwrap() {
        match value {
            Value::Object(nested)
                if !nested.contains_key("scales") && !nested.contains_key("units") =>
            {
                all.extend(flattened(value));
            }
            _ => all.push((name.clone(), value.clone())),
        }
    }
    all
}

#[test]
fn every_option_of_every_job_is_the_tools_with_the_librarys_default() {
    let defaults = defaults();
    for (job, command) in COMMANDS {
        let help = options_help(command);
        for (name, value) in flattened(&defaults[job]) {
            if LIBRARY_ONLY.contains(&name.as_str()) {
                continue;
            }
            let flag = name.replace('_', "-");
            let Some(text) = help.get(&flag) else {
                panic!("`crestline {command}` has no --{flag} for the library's {job}.{name}");
            };
            // An option without a default of its own (null) may describe the
            // default that depends on the input in words.
            if let (Some(shown), false) = (shown_default(text), value.is_null()) {
                assert!(
                    same_default(&shown, &value),
                    "`crestline {command} --{flag}` shows the default {shown}, the library's is {value}"
                );
            }
        }
    }
}

#[test]
fn the_check_tells_a_default_that_differs() {
    assert!(same_default("2", &serde_json::json!(2.0)));
    assert!(!same_default("3", &serde_json::json!(2.0)));
    assert!(same_default(
        "1.5 scales",
        &serde_json::json!({"scales": 1.5})
    ));
    assert!(!same_default("1.5", &serde_json::json!({"scales": 1.5})));
    assert!(same_default("auto", &serde_json::json!("auto")));
    assert!(!same_default("true", &serde_json::json!(false)));
    assert!(same_default("800x600", &serde_json::json!([800, 600])));
    assert!(!same_default("600x800", &serde_json::json!([800, 600])));
    assert!(same_default(
        "24 16 10",
        &serde_json::json!([24.0, 16.0, 10.0])
    ));
    let help = "      --sigma <S>  smoothing [default: \"1 scale\"]";
    assert_eq!(shown_default(help).as_deref(), Some("1 scale"));
}
