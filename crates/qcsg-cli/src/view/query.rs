//! The query strings of `/frame.png`, `/pick` and `/camera`, read strictly: every value checked
//! and its limit enforced, every mistake a 400 answer saying what was wrong and how to fix it
//! (`docs/view.md`). The parameters and their defaults are those of `qcsg render`.

use axum::http::StatusCode;
use qcsg_lsp::preview::ViewRequest;
use qcsg_render::{ImageSize, Projection, View};
use serde::Serialize;

/// The largest frame the server renders, set by `--max-size`.
#[derive(Clone, Copy, Debug)]
pub struct SizeLimit {
    /// Most pixels across.
    pub width: u32,
    /// Most pixels down.
    pub height: u32,
}

/// A request the server refuses: its status and a diagnostic-like body.
#[derive(Debug, Serialize)]
pub struct Refusal {
    /// The HTTP status (4xx).
    #[serde(skip)]
    pub status: StatusCode,
    /// What was wrong.
    pub message: String,
    /// How to do it right, when there is something to say.
    pub help: Option<String>,
}

impl Refusal {
    /// A 400 answer.
    pub fn bad_request(message: impl Into<String>) -> Self {
        Self {
            status: StatusCode::BAD_REQUEST,
            message: message.into(),
            help: None,
        }
    }

    /// The same refusal with help.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }
}

/// The parameters of a frame: `width`, `height`, `camera`, `projection`.
const VIEW_PARAMETERS: &[&str] = &["width", "height", "camera", "projection"];

/// Reads a frame's parameters (no others allowed).
pub fn view_request(query: Option<&str>, limit: SizeLimit) -> Result<ViewRequest, Refusal> {
    let pairs = pairs(query, VIEW_PARAMETERS)?;
    view_from(&pairs, limit)
}

/// Reads a pick's parameters: a frame's and the pixel `x`, `y` (both required, inside it).
pub fn pick_request(
    query: Option<&str>,
    limit: SizeLimit,
) -> Result<(ViewRequest, u32, u32), Refusal> {
    let pairs = pairs(query, &[VIEW_PARAMETERS, &["x", "y"]].concat())?;
    let request = view_from(&pairs, limit)?;
    let coordinate = |name: &str, below: u32| -> Result<u32, Refusal> {
        let text = lookup(&pairs, name).ok_or_else(|| {
            Refusal::bad_request(format!("`{name}` is missing"))
                .with_help("give the pixel as x=X&y=Y, counted from the top left of the frame")
        })?;
        let value: u32 = text.parse().map_err(|_| {
            Refusal::bad_request(format!(
                "`{name}` must be a whole number of pixels, found `{text}`"
            ))
        })?;
        if value >= below {
            return Err(Refusal::bad_request(format!(
                "`{name}={value}` lies outside the frame, which is {below} pixels along it"
            )));
        }
        Ok(value)
    };
    let x = coordinate("x", request.size.width())?;
    let y = coordinate("y", request.size.height())?;
    Ok((request, x, y))
}

fn view_from(pairs: &[(String, String)], limit: SizeLimit) -> Result<ViewRequest, Refusal> {
    let dimension = |name: &str, default: u32, max: u32| -> Result<u32, Refusal> {
        let Some(text) = lookup(pairs, name) else {
            return Ok(default);
        };
        let value: u32 = text.parse().map_err(|_| {
            Refusal::bad_request(format!(
                "`{name}` must be a whole number of pixels, found `{text}`"
            ))
        })?;
        if value == 0 {
            return Err(Refusal::bad_request(format!("`{name}` must be at least 1")));
        }
        if value > max {
            return Err(Refusal::bad_request(format!(
                "`{name}={value}` is over the limit of {max} pixels"
            ))
            .with_help(format!(
                "start `qcsg view` with `--max-size {},{}` to allow it",
                if name == "width" { value } else { limit.width },
                if name == "height" {
                    value
                } else {
                    limit.height
                },
            )));
        }
        Ok(value)
    };
    let width = dimension("width", ImageSize::DEFAULT.width(), limit.width)?;
    let height = dimension("height", ImageSize::DEFAULT.height(), limit.height)?;
    let size = ImageSize::new(width, height)
        .map_err(|error| Refusal::bad_request(format!("bad size: {error}")))?;
    let view = match lookup(pairs, "camera") {
        None => View::Iso,
        Some(text) => View::parse(text).map_err(|error| {
            Refusal::bad_request(format!("bad `camera`: {error}")).with_help(
                "a named view (iso, front, top, right) or eye_x,eye_y,eye_z,center_x,center_y,center_z",
            )
        })?,
    };
    let projection = match lookup(pairs, "projection") {
        None | Some("perspective") => Projection::Perspective,
        Some("ortho") => Projection::Orthographic,
        Some(other) => {
            return Err(Refusal::bad_request(format!("bad `projection`: `{other}`"))
                .with_help("`perspective` or `ortho`"));
        }
    };
    Ok(ViewRequest {
        size,
        view,
        projection,
    })
}

fn lookup<'a>(pairs: &'a [(String, String)], name: &str) -> Option<&'a str> {
    pairs
        .iter()
        .find(|(key, _)| key == name)
        .map(|(_, value)| value.as_str())
}

/// The decoded `name=value` pairs of a query; an unknown or repeated name is refused, so a
/// misspelt parameter is never silently ignored.
fn pairs(query: Option<&str>, known: &[&str]) -> Result<Vec<(String, String)>, Refusal> {
    let mut pairs: Vec<(String, String)> = Vec::new();
    for part in query.unwrap_or("").split('&').filter(|p| !p.is_empty()) {
        let (name, value) = part.split_once('=').unwrap_or((part, ""));
        let (name, value) = (decode(name)?, decode(value)?);
        if !known.contains(&name.as_str()) {
            return Err(Refusal::bad_request(format!("unknown parameter `{name}`"))
                .with_help(format!("the parameters here are: {}", known.join(", "))));
        }
        if pairs.iter().any(|(seen, _)| *seen == name) {
            return Err(Refusal::bad_request(format!("`{name}` is given twice")));
        }
        pairs.push((name, value));
    }
    Ok(pairs)
}

/// Percent-decoding of one query component (`+` is a space), refusing bad escapes and text
/// that is not UTF-8.
fn decode(text: &str) -> Result<String, Refusal> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' => {
                let hex = bytes
                    .get(i + 1..i + 3)
                    .and_then(|h| std::str::from_utf8(h).ok())
                    .and_then(|h| u8::from_str_radix(h, 16).ok())
                    .ok_or_else(|| Refusal::bad_request("a bad %-escape in the query"))?;
                out.push(hex);
                i += 2;
            }
            byte => out.push(byte),
        }
        i += 1;
    }
    String::from_utf8(out).map_err(|_| Refusal::bad_request("the query is not UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMIT: SizeLimit = SizeLimit {
        width: 4096,
        height: 4096,
    };

    #[test]
    fn defaults_are_those_of_qcsg_render() {
        let request = view_request(None, LIMIT).unwrap();
        assert_eq!(request.size, ImageSize::DEFAULT);
        assert_eq!(request.view, View::Iso);
        assert_eq!(request.projection, Projection::Perspective);
    }

    #[test]
    fn values_are_decoded_and_checked() {
        let request = view_request(
            Some("width=64&height=48&camera=1%2C2%2C3,0,0,0&projection=ortho"),
            LIMIT,
        )
        .unwrap();
        assert_eq!(request.size, ImageSize::new(64, 48).unwrap());
        assert!(matches!(request.view, View::Explicit { .. }));
        assert_eq!(request.projection, Projection::Orthographic);
        for bad in [
            "width=abc",
            "width=0",
            "width=-3",
            "height=5000",
            "camera=sideways",
            "camera=0,0,0,0,0,0",
            "projection=fisheye",
            "zoom=2",
            "width=3&width=4",
            "camera=%zz",
            "camera=%ff",
        ] {
            let refusal = view_request(Some(bad), LIMIT).unwrap_err();
            assert_eq!(refusal.status, StatusCode::BAD_REQUEST, "{bad}");
        }
        let over = view_request(Some("width=5000"), LIMIT).unwrap_err();
        assert!(over.message.contains("limit of 4096"), "{}", over.message);
        assert!(over.help.unwrap().contains("--max-size 5000,4096"));
    }

    #[test]
    fn a_pick_needs_a_pixel_inside_the_frame() {
        let (_, x, y) = pick_request(Some("width=10&height=10&x=9&y=0"), LIMIT).unwrap();
        assert_eq!((x, y), (9, 0));
        for bad in [
            "width=10&height=10&x=10&y=0",
            "x=1",
            "x=a&y=1",
            "x=1&y=1&z=1",
        ] {
            assert!(pick_request(Some(bad), LIMIT).is_err(), "{bad}");
        }
    }
}
