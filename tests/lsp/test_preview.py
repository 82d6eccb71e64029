"""The preview panel's custom requests (docs/view.md): `qcsg/frame`, `qcsg/pick` and
`qcsg/partsAt`, answered from the unsaved text of an open document."""

import base64

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcInvalidParams

from conftest import open_document, position_of

SCENE = """module post(h) {
    cylinder(h = h, r = 2);
}
translate([-6, 0, 0]) post(8);
sphere(r = 4);
"""


def as_dict(value):
    """pygls hands unknown answers back as objects with attributes; make plain data of them."""
    if hasattr(value, "_asdict"):
        return {k: as_dict(v) for k, v in value._asdict().items()}
    if isinstance(value, (list, tuple)):
        return [as_dict(v) for v in value]
    if hasattr(value, "__dict__") and not isinstance(value, type):
        return {k: as_dict(v) for k, v in vars(value).items()}
    return value


async def request(client, method, params):
    return as_dict(await client.protocol.send_request_async(method, params))


FRAME = {"width": 96, "height": 64, "camera": "front", "projection": "ortho"}


async def test_frames_follow_unsaved_edits(client, tmp_path):
    uri = open_document(client, tmp_path / "scene.qcsg", SCENE)
    first = await request(client, "qcsg/frame", {"textDocument": {"uri": uri}, **FRAME})
    png = base64.b64decode(first["png"])
    assert png.startswith(b"\x89PNG")
    assert first["quadrics"] > 0
    # An unsaved change: the next frame shows it.
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=SCENE.replace("r = 4", "r = 7"))],
        )
    )
    second = await request(client, "qcsg/frame", {"textDocument": {"uri": uri}, **FRAME})
    assert base64.b64decode(second["png"]) != png
    # A syntax error: no frame, the panel keeps its image.
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=3),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text="sphere(r = ;\n")],
        )
    )
    broken = await request(client, "qcsg/frame", {"textDocument": {"uri": uri}, **FRAME})
    assert broken["png"] is None


async def test_a_pick_names_the_call_and_the_module_chain(client, tmp_path):
    uri = open_document(client, tmp_path / "scene.qcsg", SCENE)
    # The post stands left of the ball: scan the front view's left third for it.
    found = None
    for x in range(4, 40, 4):
        picked = await request(client, "qcsg/pick", {"textDocument": {"uri": uri}, **FRAME, "x": x, "y": 32})
        if picked and picked["range"]["start"]["line"] == 1:
            found = picked
            break
    assert found, "no pixel of the post"
    assert found["file"].endswith("scene.qcsg")
    assert [call["module"] for call in found["chain"]] == ["post"]
    assert found["chain"][0]["range"]["start"]["line"] == 3
    centre = await request(client, "qcsg/pick", {"textDocument": {"uri": uri}, **FRAME, "x": 60, "y": 32})
    assert centre["range"]["start"]["line"] == 4 and centre["chain"] == []
    corner = await request(client, "qcsg/pick", {"textDocument": {"uri": uri}, **FRAME, "x": 0, "y": 0})
    assert corner is None


async def test_parts_at_the_cursor_are_tinted(client, tmp_path):
    uri = open_document(client, tmp_path / "scene.qcsg", SCENE)
    at = position_of(SCENE, "sphere(r", shift=2)
    parts = await request(
        client, "qcsg/partsAt", {"textDocument": {"uri": uri}, "position": {"line": at.line, "character": at.character}}
    )
    assert parts, "the ball's quadrics"
    plain = await request(client, "qcsg/frame", {"textDocument": {"uri": uri}, **FRAME})
    tinted = await request(client, "qcsg/frame", {"textDocument": {"uri": uri}, **FRAME, "highlight": parts})
    assert plain["png"] != tinted["png"]
    nothing = await request(client, "qcsg/partsAt", {"textDocument": {"uri": uri}, "position": {"line": 0, "character": 0}})
    assert nothing == []


@pytest.mark.parametrize(
    "bad",
    [
        {"width": 0},
        {"width": 5000},
        {"camera": "sideways"},
        {"projection": "fisheye"},
        {"zoom": 2},
        {"x": 96, "y": 0},
    ],
)
async def test_bad_values_are_invalid_params(client, tmp_path, bad):
    uri = open_document(client, tmp_path / "scene.qcsg", SCENE)
    method = "qcsg/pick" if "x" in bad else "qcsg/frame"
    with pytest.raises(JsonRpcInvalidParams):
        await request(client, method, {"textDocument": {"uri": uri}, **FRAME, **bad})
