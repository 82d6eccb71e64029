//! The preview panel's custom requests, answered from the unsaved text of an open document:
//!
//! - `qcsg/frame` `{textDocument, width, height, camera, projection, highlight?}`: the PNG
//!   (base64) that `qcsg render` makes with those arguments, the parts of `highlight` (quadric
//!   indices) tinted, with the camera's eye and centre;
//! - `qcsg/pick` `{textDocument, width, height, camera, projection, x, y}`: what that pixel
//!   shows (`null`: the background), as `qcsg view`'s `/pick`;
//! - `qcsg/partsAt` `{textDocument, position}`: the quadrics made by the primitive call at the
//!   position, for the panel to tint.
//!
//! Values are checked as `qcsg view` checks its queries (docs/view.md); a bad one is an
//! `InvalidParams` error saying what is wrong. A program with errors has no frame: the answer
//! says so (`png: null`) and the panel keeps its last image.

use std::time::Instant;

use qcsg_diag::LineCol;
use qcsg_render::{ImageSize, Projection, View};
use serde::Deserialize;
use serde_json::{Value, json};
use tower_lsp_server::jsonrpc::{Error, Result};
use tower_lsp_server::ls_types::{Position, TextDocumentIdentifier};

use crate::preview::ViewRequest;
use crate::server::Backend;

/// The largest frame the panel may ask for, in each direction (as `qcsg view`'s default).
pub const MAX_FRAME_SIDE: u32 = 4096;

/// The parameters of a frame.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct FrameParams {
    text_document: TextDocumentIdentifier,
    width: u32,
    height: u32,
    #[serde(default)]
    camera: Option<String>,
    #[serde(default)]
    projection: Option<String>,
    #[serde(default)]
    highlight: Option<Vec<u32>>,
    #[serde(default)]
    x: Option<u32>,
    #[serde(default)]
    y: Option<u32>,
}

/// The parameters of `qcsg/partsAt`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct PartsParams {
    text_document: TextDocumentIdentifier,
    position: Position,
}

fn invalid(message: impl Into<String>) -> Error {
    Error::invalid_params(message.into())
}

impl FrameParams {
    fn request(&self) -> Result<ViewRequest> {
        for (name, value) in [("width", self.width), ("height", self.height)] {
            if value == 0 || value > MAX_FRAME_SIDE {
                return Err(invalid(format!(
                    "`{name}` must be 1 to {MAX_FRAME_SIDE} pixels, found {value}"
                )));
            }
        }
        let size = ImageSize::new(self.width, self.height).map_err(|e| invalid(e.to_string()))?;
        let view = match &self.camera {
            None => View::Iso,
            Some(text) => View::parse(text).map_err(|e| invalid(format!("bad `camera`: {e}")))?,
        };
        let projection = match self.projection.as_deref() {
            None | Some("perspective") => Projection::Perspective,
            Some("ortho") => Projection::Orthographic,
            Some(other) => return Err(invalid(format!("bad `projection`: `{other}`"))),
        };
        Ok(ViewRequest {
            size,
            view,
            projection,
        })
    }
}

impl Backend {
    /// `qcsg/frame`.
    pub async fn preview_frame(&self, params: FrameParams) -> Result<Value> {
        let request = params.request()?;
        let highlight = params.highlight.unwrap_or_default();
        let answer = self
            .query(&params.text_document.uri, move |analyzed| {
                let Some(preview) = analyzed.geometry().and_then(|g| g.preview()) else {
                    let reason = if analyzed.is_superseded() {
                        "the document changed before this frame was drawn"
                    } else {
                        "the program has errors"
                    };
                    return Ok(json!({"png": null, "reason": reason}));
                };
                let started = Instant::now();
                let frame = preview
                    .render_highlighted(&request, &highlight)
                    .map_err(|e| invalid(format!("bad camera: {e}")))?;
                let png = qcsg_render::png::encode(&frame).map_err(|e| {
                    let mut error = Error::internal_error();
                    error.message = e.to_string().into();
                    error
                })?;
                // The camera, so that the panel can turn a named view from where it is.
                let camera = request.camera(preview.scene()).ok();
                let bounds = preview.scene().bounds();
                let bounded = !bounds.is_empty() && bounds.is_bounded();
                let center = match request.view {
                    View::Explicit { center, .. } => center.to_array(),
                    _ if bounded => bounds.centre().to_array(),
                    _ => [0.0; 3],
                };
                Ok(json!({
                    "png": base64(&png),
                    "eye": camera.map(|c| c.eye().to_array()),
                    "center": center,
                    "radius": if bounded { bounds.half_diagonal() } else { 1.0 },
                    "renderMs": started.elapsed().as_secs_f64() * 1e3,
                    "quadrics": preview.scene().quadric_count(),
                }))
            })
            .await?;
        answer.unwrap_or_else(|| Err(invalid("the document is not open")))
    }

    /// `qcsg/pick`.
    pub async fn preview_pick(&self, params: FrameParams) -> Result<Value> {
        let request = params.request()?;
        let (Some(x), Some(y)) = (params.x, params.y) else {
            return Err(invalid("`x` and `y` are required"));
        };
        if x >= request.size.width() || y >= request.size.height() {
            return Err(invalid(format!("({x}, {y}) lies outside the frame")));
        }
        let answer = self
            .query(&params.text_document.uri, move |analyzed| {
                let Some(geometry) = analyzed.geometry() else {
                    return Ok(Value::Null);
                };
                let Some(preview) = geometry.preview() else {
                    return Ok(Value::Null);
                };
                let picked = preview
                    .pick(&geometry.evaluation().dag, &request, x, y)
                    .map_err(|e| invalid(format!("bad camera: {e}")))?;
                Ok(serde_json::to_value(picked).unwrap_or(Value::Null))
            })
            .await?;
        answer.unwrap_or_else(|| Err(invalid("the document is not open")))
    }

    /// `qcsg/partsAt`.
    pub async fn preview_parts_at(&self, params: PartsParams) -> Result<Value> {
        let position = params.position;
        let answer = self
            .query(&params.text_document.uri, move |analyzed| {
                let analysis = analyzed.analysis();
                let Some(preview) = analyzed.geometry().and_then(|g| g.preview()) else {
                    return json!([]);
                };
                let main = analysis.main();
                let file = analysis.sema().sources.get(main);
                let offset = file.line_index.offset(
                    &file.text,
                    LineCol {
                        line: position.line,
                        character: position.character,
                    },
                );
                json!(preview.quadrics_at(main, offset as u32))
            })
            .await?;
        Ok(answer.unwrap_or_else(|| json!([])))
    }
}

/// Standard base64 with padding (RFC 4648), for the PNG in a JSON answer.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::base64;

    #[test]
    fn base64_matches_rfc_4648() {
        for (input, output) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(input.as_bytes()), output);
        }
    }
}
