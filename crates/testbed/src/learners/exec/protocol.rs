//! The learner protocol's messages (`book/src/learner/protocol.md`), one JSON
//! object per line, and the checks on what a learner says: no I/O here.

use scasm::declaration::{Kind, Setting};
use scasm::{Draw, Event, MAX_COEFFS, Polynomial, Posterior};
use serde::Deserialize;
use serde_json::{Value, json};

/// The protocol version this host speaks.
pub const VERSION: u32 = 1;

/// The longest piece of a learner's line quoted in an error.
const QUOTE_CHARS: usize = 160;

/// A setting as a learner's hello declares it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct SettingLine {
    key: String,
    default: f64,
    #[serde(default)]
    min: Option<f64>,
    #[serde(default)]
    max: Option<f64>,
    #[serde(default)]
    integer: bool,
    #[serde(default)]
    doc: String,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct HelloLine {
    protocol: u32,
    name: String,
    #[serde(default)]
    about: String,
    #[serde(default)]
    settings: Vec<SettingLine>,
    #[serde(default)]
    posterior: bool,
}

/// What a learner says first: who it is and the settings it takes.
#[derive(Debug, Clone, PartialEq)]
pub struct Hello {
    /// Its name in reports and in its settings' keys (`learner.<name>.<key>`).
    pub name: String,
    /// One line on what it is.
    pub about: String,
    /// Its own settings, as declared.
    pub settings: Vec<Setting>,
    /// Whether it answers `posterior` at the end of a trial.
    pub posterior: bool,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelsLine {
    action: Option<Vec<f64>>,
    sensor: Option<Vec<f64>>,
    x_a: Option<f64>,
    x_s: Option<f64>,
}

/// A learner's answer to a query: its current models and locations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Models {
    /// The action model (command -> location units per second), if any yet.
    pub action: Option<Polynomial>,
    /// The sensor model (pixels -> location units), if any yet.
    pub sensor: Option<Polynomial>,
    /// Its dead-reckoned location.
    pub x_a: Option<f64>,
    /// Its location from the latest reading.
    pub x_s: Option<f64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct DrawLine {
    action: Vec<f64>,
    sensor: Vec<(f64, f64)>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct PosteriorLine {
    draws: Option<Vec<DrawLine>>,
}

/// The most points a draw's sensor table may have: the host's 200 draws of
/// this many points, written in full, are about half a line's bound
/// ([`super::child::MAX_LINE_BYTES`]).
pub const MAX_TABLE_POINTS: usize = 64;

/// What a line from a learner is, once read.
#[derive(Debug, Clone, PartialEq)]
pub enum Said {
    /// Its hello.
    Hello(Hello),
    /// An answer to a query.
    Models(Models),
    /// An answer to `posterior`: its draws, or none.
    Posterior(Option<Posterior>),
    /// It refuses to go on, and says why.
    Error(String),
}

/// `text` cut to a quotable length.
fn quote(text: &str) -> String {
    let cut: String = text.chars().take(QUOTE_CHARS).collect();
    if cut.len() < text.len() {
        format!("{cut}...")
    } else {
        cut
    }
}

/// Reads one line a learner wrote, or says how it is not the protocol.
pub fn parse(line: &str) -> Result<Said, String> {
    let not_protocol = |why: String| {
        format!(
            "wrote a line that is not the protocol ({why}): `{}` (a learner writes only \
             protocol lines to stdout; logs go to stderr)",
            quote(line)
        )
    };
    let value: Value = serde_json::from_str(line).map_err(|e| {
        if ["NaN", "Infinity"].iter().any(|t| line.contains(t)) {
            format!(
                "answered a number that is not finite (NaN and Infinity are not JSON): `{}`",
                quote(line)
            )
        } else {
            not_protocol(e.to_string())
        }
    })?;
    let kind = value
        .get("type")
        .and_then(Value::as_str)
        .ok_or_else(|| not_protocol("no string \"type\"".into()))?
        .to_string();
    let mut body = value;
    if let Some(map) = body.as_object_mut() {
        map.remove("type");
    }
    let fields = |e: serde_json::Error| not_protocol(format!("a `{kind}` message: {e}"));
    match kind.as_str() {
        "hello" => hello(serde_json::from_value(body).map_err(fields)?).map(Said::Hello),
        "models" => models(serde_json::from_value(body).map_err(fields)?).map(Said::Models),
        "posterior" => {
            posterior(serde_json::from_value(body).map_err(fields)?).map(Said::Posterior)
        }
        "error" => {
            #[derive(Deserialize)]
            #[serde(deny_unknown_fields)]
            struct ErrorLine {
                message: String,
            }
            let e: ErrorLine = serde_json::from_value(body).map_err(fields)?;
            Ok(Said::Error(e.message))
        }
        other => Err(not_protocol(format!(
            "unknown type `{other}`; a learner says hello, models, posterior or error"
        ))),
    }
}

/// A hello, checked: the version, a name that can be part of a key, and
/// settings whose defaults are in their ranges.
fn hello(h: HelloLine) -> Result<Hello, String> {
    if h.protocol != VERSION {
        return Err(format!(
            "speaks protocol version {}; this host speaks version {VERSION}",
            h.protocol
        ));
    }
    let word = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    };
    if !word(&h.name) {
        return Err(format!(
            "calls itself `{}`: a learner's name is letters, digits, `-` and `_` (it is part of \
             its settings' keys, learner.<name>.<key>)",
            quote(&h.name)
        ));
    }
    let mut settings: Vec<Setting> = Vec::new();
    for s in h.settings {
        if !word(&s.key) || s.key.contains('-') {
            return Err(format!(
                "declares a setting `{}`: a key is letters, digits and `_`",
                quote(&s.key)
            ));
        }
        if settings.iter().any(|d| d.key == s.key) {
            return Err(format!("declares the setting `{}` twice", s.key));
        }
        let kind = if s.integer { Kind::Count } else { Kind::Number };
        let (min, max) = (
            s.min.unwrap_or(f64::NEG_INFINITY),
            s.max.unwrap_or(f64::INFINITY),
        );
        let setting = Setting::new(&s.key, kind, s.default, (min, false, max), &s.doc);
        setting.check(s.default).map_err(|e| {
            format!(
                "declares `{}` with a default that is not allowed: {e}",
                s.key
            )
        })?;
        settings.push(setting);
    }
    Ok(Hello {
        name: h.name,
        about: h.about,
        settings,
        posterior: h.posterior,
    })
}

/// The host's request for `draws` draws of the learner's posterior.
pub fn posterior_request(draws: usize) -> String {
    json!({"type": "posterior", "draws": draws}).to_string()
}

/// A posterior, checked: each draw an action model of 1 to [`MAX_COEFFS`]
/// finite coefficients and a sensor table of 2 to [`MAX_TABLE_POINTS`]
/// finite points whose readings are positive and increasing; at least one
/// draw, or null (none).
fn posterior(p: PosteriorLine) -> Result<Option<Posterior>, String> {
    let Some(lines) = p.draws else {
        return Ok(None);
    };
    if lines.is_empty() {
        return Err("answered a posterior of no draws (null says it has none)".into());
    }
    let mut draws = Vec::with_capacity(lines.len());
    for (i, d) in lines.into_iter().enumerate() {
        let action = Polynomial::new(&d.action)
            .filter(Polynomial::is_finite)
            .ok_or_else(|| {
                format!(
                    "answered draw {i} with an impossible action model {:?}: 1 to {MAX_COEFFS} \
                     finite coefficients, lowest power first",
                    d.action
                )
            })?;
        let table = &d.sensor;
        let fault = if !(2..=MAX_TABLE_POINTS).contains(&table.len()) {
            Some(format!("{} points (2 to {MAX_TABLE_POINTS})", table.len()))
        } else if let Some(&(obs, x)) = table
            .iter()
            .find(|(obs, x)| !(obs.is_finite() && x.is_finite() && *obs > 0.0))
        {
            Some(format!(
                "the point [{obs}, {x}] (a positive reading, a finite location)"
            ))
        } else {
            table
                .windows(2)
                .find(|w| w[1].0 <= w[0].0)
                .map(|w| format!("readings not increasing ({} then {})", w[0].0, w[1].0))
        };
        if let Some(why) = fault {
            return Err(format!(
                "answered draw {i} with an impossible sensor table: {why}; a table is \
                 [[reading px, location], ...] sorted by reading"
            ));
        }
        draws.push(Draw {
            action,
            sensor: d.sensor,
        });
    }
    Ok(Some(Posterior { draws }))
}

/// An answer, checked: models of 1 to [`MAX_COEFFS`] finite coefficients,
/// finite locations.
fn models(m: ModelsLine) -> Result<Models, String> {
    let polynomial = |which: &str, c: Option<Vec<f64>>| -> Result<Option<Polynomial>, String> {
        let Some(c) = c else { return Ok(None) };
        Polynomial::new(&c)
            .filter(Polynomial::is_finite)
            .map(Some)
            .ok_or_else(|| {
                format!(
                    "answered an impossible {which} model {c:?}: a model is 1 to {MAX_COEFFS} \
                     finite coefficients, lowest power first, or null"
                )
            })
    };
    let location = |which: &str, x: Option<f64>| match x {
        Some(v) if !v.is_finite() => Err(format!("answered {which} = {v}")),
        other => Ok(other),
    };
    Ok(Models {
        action: polynomial("action", m.action)?,
        sensor: polynomial("sensor", m.sensor)?,
        x_a: location("x_a", m.x_a)?,
        x_s: location("x_s", m.x_s)?,
    })
}

/// The host's answer to a hello: the learner's own settings in force and
/// the shared ones (`learner.gamma`, the degrees, and the command scale).
/// A setting declared integer (its own by its hello, a shared one by its
/// declaration) is written as a JSON integer.
pub fn settings_line(
    own: &[(String, f64)],
    declared: &[Setting],
    shared: &[(&str, f64)],
) -> String {
    let own: serde_json::Map<String, Value> = own
        .iter()
        .map(|(k, v)| {
            let integer = declared
                .iter()
                .any(|d| &d.key == k && d.kind == Kind::Count);
            (k.clone(), number(*v, integer))
        })
        .collect();
    let shared: serde_json::Map<String, Value> = shared
        .iter()
        .map(|(k, v)| {
            let integer = scasm::declaration::shared(k).is_some_and(|s| s.kind == Kind::Count);
            ((*k).to_string(), number(*v, integer))
        })
        .collect();
    json!({"type": "settings", "protocol": VERSION, "settings": own, "shared": shared}).to_string()
}

/// `v` as JSON: an integer where `integer` and it is a whole number a double
/// holds exactly, else a number as written.
fn number(v: f64, integer: bool) -> Value {
    const EXACT: f64 = 9_007_199_254_740_992.0; // 2^53
    if integer && v.fract() == 0.0 && v.abs() <= EXACT {
        // Whole and within 2^53: the conversion is exact.
        #[allow(clippy::cast_possible_truncation)]
        let i = v as i64;
        json!(i)
    } else {
        json!(v)
    }
}

/// An event, as a line.
pub fn event_line(event: Event) -> String {
    match event {
        Event::Command { t_s, dt_s, command } => {
            json!({"type": "command", "t_s": t_s, "dt_s": dt_s, "command": command})
        }
        Event::Reading { t_s, obs_px } => json!({"type": "reading", "t_s": t_s, "obs_px": obs_px}),
    }
    .to_string()
}

/// The query for the learner's models.
pub const QUERY: &str = r#"{"type":"query"}"#;

/// The end of the trial.
pub const END: &str = r#"{"type":"end"}"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_settings_reach_the_learner_as_integers() {
        let line = r#"{"type":"hello","protocol":1,"name":"mine","settings":[
            {"key":"k","default":2,"min":1,"max":3,"integer":true},{"key":"g","default":0.5}]}"#
            .replace('\n', "");
        let Ok(Said::Hello(h)) = parse(&line) else {
            panic!("{:?}", parse(&line))
        };
        let text = settings_line(
            &[("k".into(), 3.0), ("g".into(), 2.0)],
            &h.settings,
            &[
                ("sensor_degree", 3.0),
                ("gamma", 0.999),
                ("command_scale", 300.0),
            ],
        );
        let v: Value = serde_json::from_str(&text).expect("json");
        // Declared integer: an integer; a number that happens to be whole: a number.
        assert!(v["settings"]["k"].is_i64(), "{text}");
        assert!(v["settings"]["g"].is_f64(), "{text}");
        assert!(v["shared"]["sensor_degree"].is_i64(), "{text}");
        assert!(v["shared"]["gamma"].is_f64(), "{text}");
        assert!(v["shared"]["command_scale"].is_f64(), "{text}");
    }

    #[test]
    fn a_hello_is_read_and_checked() {
        let line = r#"{"type":"hello","protocol":1,"name":"mine","settings":[
            {"key":"k","default":2,"min":1,"max":3,"integer":true,"doc":"a count"}]}"#
            .replace('\n', "");
        let Ok(Said::Hello(h)) = parse(&line) else {
            panic!("{:?}", parse(&line))
        };
        assert_eq!(
            (h.name.as_str(), h.settings[0].range()),
            ("mine", "1..=3".into())
        );
        let other = line.replace("\"protocol\":1", "\"protocol\":2");
        assert!(parse(&other).is_err_and(|e| e.contains("version 2")));
        let bad_default = line.replace("\"default\":2", "\"default\":7");
        assert!(parse(&bad_default).is_err_and(|e| e.contains("default")));
        let dotted = line.replace("\"mine\"", "\"my.learner\"");
        assert!(parse(&dotted).is_err_and(|e| e.contains("calls itself")));
    }

    #[test]
    fn answers_that_are_not_models_are_refused_with_the_reason() {
        let ok = r#"{"type":"models","action":[0,1],"sensor":null,"x_a":1.5,"x_s":null}"#;
        assert!(
            matches!(parse(ok), Ok(Said::Models(m)) if m.action.is_some() && m.sensor.is_none())
        );
        let nan = ok.replace("1.5", "NaN");
        assert!(parse(&nan).is_err_and(|e| e.contains("not finite")));
        let empty = ok.replace("[0,1]", "[]");
        assert!(parse(&empty).is_err_and(|e| e.contains("impossible action")));
        let long = ok.replace("[0,1]", "[0,1,2,3,4,5,6,7,8,9]");
        assert!(parse(&long).is_err_and(|e| e.contains("impossible")));
        let typo = ok.replace("\"action\"", "\"acton\"");
        assert!(parse(&typo).is_err_and(|e| e.contains("not the protocol")));
        assert!(parse("hello world").is_err_and(|e| e.contains("stderr")));
        assert_eq!(
            parse(r#"{"type":"error","message":"no"}"#),
            Ok(Said::Error("no".into()))
        );
    }

    #[test]
    fn a_posterior_is_read_and_each_draw_checked() {
        let ok = r#"{"type":"posterior","draws":[{"action":[0,1],"sensor":[[10,3],[20,1.5]]}]}"#;
        let Ok(Said::Posterior(Some(p))) = parse(ok) else {
            panic!("{:?}", parse(ok));
        };
        assert_eq!(p.draws.len(), 1);
        assert_eq!(p.draws[0].sensor, vec![(10.0, 3.0), (20.0, 1.5)]);
        assert_eq!(
            parse(r#"{"type":"posterior","draws":null}"#),
            Ok(Said::Posterior(None))
        );
        for (bad, says) in [
            (
                ok.replace("[[10,3],[20,1.5]]", "[[10,3]]"),
                "1 points (2 to 64)",
            ),
            (
                ok.replace("[20,1.5]", "[10,1.5]"),
                "readings not increasing",
            ),
            (ok.replace("[10,3]", "[-1,3]"), "a positive reading"),
            (ok.replace("[0,1]", "[]"), "impossible action model"),
            (ok.replace("1.5", "NaN"), "not finite"),
            (
                r#"{"type":"posterior","draws":[]}"#.into(),
                "no draws (null says it has none)",
            ),
            (ok.replace("\"sensor\"", "\"table\""), "not the protocol"),
        ] {
            assert!(
                parse(&bad).is_err_and(|e| e.contains(says)),
                "{bad}: {says}"
            );
        }
        let hello = r#"{"type":"hello","protocol":1,"name":"mine","posterior":true}"#;
        assert!(matches!(parse(hello), Ok(Said::Hello(h)) if h.posterior));
    }

    #[test]
    fn events_are_written_exactly() {
        let e = Event::Reading {
            t_s: 0.1 + 0.2,
            obs_px: 1.0 / 3.0,
        };
        let v: Value = serde_json::from_str(&event_line(e)).unwrap_or_default();
        assert_eq!(v["t_s"].as_f64(), Some(0.1 + 0.2));
        assert_eq!(v["obs_px"].as_f64(), Some(1.0 / 3.0));
    }
}
