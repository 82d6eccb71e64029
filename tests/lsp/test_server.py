"""End-to-end tests of `qcsg lsp` through a real client over stdio, one per feature."""

import asyncio

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from conftest import diagnostics_until, open_document, position_of

PROGRAM = """include <lib.scad>
/// Width of the plate.
width = 10 * 2;
module plate(w, thickness = 1) {
    cube([w, w, thickness]);
}
function twice(x) = 2 * x;
plate(width, 3);
part(lib_width);
echo(twice(width));
"""

LIBRARY = "/// A library part.\nmodule part(size = 2) cube(size);\nlib_width = 3;\n"


def doc(uri):
    return types.TextDocumentIdentifier(uri=uri)


def at(uri, text, needle, nth=0, shift=0):
    """Keyword arguments naming a document and a position in it."""
    return {"text_document": doc(uri), "position": position_of(text, needle, nth, shift)}


async def open_program(client, tmp_path, text=PROGRAM):
    (tmp_path / "lib.scad").write_text(LIBRARY)
    uri = open_document(client, tmp_path / "main.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    return uri


async def test_diagnostics_on_open_and_incremental_change(client: LanguageClient, tmp_path):
    text = "width = 1;\ncube(widht);\nwidth = 2;\n"
    uri = open_document(client, tmp_path / "a.qcsg", text)
    diagnostics = await diagnostics_until(client, uri, lambda d: len(d) > 0)
    codes = {d.code for d in diagnostics}
    assert "E0101" in codes and "W0105" in codes
    undefined = next(d for d in diagnostics if d.code == "E0101")
    assert undefined.range.start == position_of(text, "widht")
    assert undefined.severity == types.DiagnosticSeverity.Error
    assert "`width`" in undefined.message
    reassigned = next(d for d in diagnostics if d.code == "W0105")
    assert reassigned.related_information, "labels become related information"

    # Fix the typo with an incremental edit, then remove the reassignment.
    start = position_of(text, "widht")
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=start, end=types.Position(line=start.line, character=start.character + 5)),
                    text="width",
                ),
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=types.Position(line=2, character=0), end=types.Position(line=3, character=0)),
                    text="",
                ),
            ],
        )
    )
    await diagnostics_until(client, uri, lambda d: len(d) == 0)


async def test_syntax_errors_are_reported_mid_edit(client: LanguageClient, tmp_path):
    uri = open_document(client, tmp_path / "b.qcsg", "module m( {\n")
    diagnostics = await diagnostics_until(client, uri, lambda d: len(d) > 0)
    assert all(d.code for d in diagnostics)
    assert any(d.severity == types.DiagnosticSeverity.Error for d in diagnostics)


async def test_utf16_positions_in_edits_and_hover(client: LanguageClient, tmp_path):
    text = 'label = "😀é"; size = 2;\ncube(size);\n'
    uri = open_document(client, tmp_path / "c.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    # `size` after the emoji: the emoji counts as two UTF-16 code units.
    start = position_of(text, "size")
    assert start.character == 15
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=types.Position(line=0, character=22), end=types.Position(line=0, character=23)),
                    text="7",
                )
            ],
        )
    )
    new_text = text.replace("size = 2", "size = 7")
    hover = await client.text_document_hover_async(types.HoverParams(**(at(uri, new_text, "size", 1))))
    assert hover is not None and "size = 7" in hover.contents.value


async def test_hover(client: LanguageClient, tmp_path):
    uri = await open_program(client, tmp_path)
    width = await client.text_document_hover_async(types.HoverParams(**(at(uri, PROGRAM, "width));", 0, 1))))
    assert "width = 20" in width.contents.value and "Width of the plate." in width.contents.value
    plate = await client.text_document_hover_async(types.HoverParams(**(at(uri, PROGRAM, "plate(width"))))
    assert "module plate(w, thickness = 1)" in plate.contents.value
    part = await client.text_document_hover_async(types.HoverParams(**(at(uri, PROGRAM, "part(lib"))))
    assert "A library part." in part.contents.value
    cube = await client.text_document_hover_async(types.HoverParams(**(at(uri, PROGRAM, "cube"))))
    assert "built-in primitive" in cube.contents.value and "cube(size, center)" in cube.contents.value
    nothing = await client.text_document_hover_async(types.HoverParams(**(at(uri, PROGRAM, "10"))))
    assert nothing is None


async def test_definition_including_into_included_files(client: LanguageClient, tmp_path):
    uri = await open_program(client, tmp_path)
    local = await client.text_document_definition_async(types.DefinitionParams(**(at(uri, PROGRAM, "width, 3"))))
    assert local.uri == uri and local.range.start == position_of(PROGRAM, "width =")
    remote = await client.text_document_definition_async(types.DefinitionParams(**(at(uri, PROGRAM, "part("))))
    assert remote.uri == (tmp_path / "lib.scad").as_uri()
    assert remote.range.start == types.Position(line=1, character=7)
    include = await client.text_document_definition_async(types.DefinitionParams(**(at(uri, PROGRAM, "lib.scad"))))
    assert include.uri == (tmp_path / "lib.scad").as_uri()


async def test_references(client: LanguageClient, tmp_path):
    uri = await open_program(client, tmp_path)
    position = at(uri, PROGRAM, "width =")
    found = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=position["text_document"],
            position=position["position"],
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    assert sorted((r.range.start.line, r.range.start.character) for r in found) == [(2, 0), (7, 6), (9, 11)]


async def test_rename(client: LanguageClient, tmp_path):
    uri = await open_program(client, tmp_path)
    prepared = await client.text_document_prepare_rename_async(types.PrepareRenameParams(**(at(uri, PROGRAM, "twice(w"))))
    assert prepared.placeholder == "twice"
    edit = await client.text_document_rename_async(
        types.RenameParams(**(at(uri, PROGRAM, "twice(w")), new_name="double")
    )
    assert len(edit.changes[uri]) == 2 and all(e.new_text == "double" for e in edit.changes[uri])
    with pytest.raises(Exception, match="built-in"):
        await client.text_document_prepare_rename_async(types.PrepareRenameParams(**(at(uri, PROGRAM, "cube"))))


async def test_symbols(client: LanguageClient, tmp_path):
    uri = await open_program(client, tmp_path)
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=doc(uri)))
    assert [(s.name, s.kind) for s in symbols] == [
        ("width", types.SymbolKind.Variable),
        ("plate", types.SymbolKind.Module),
        ("twice", types.SymbolKind.Function),
    ]
    found = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="part"))
    assert [s.name for s in found] == ["part"]
    assert found[0].location.uri == (tmp_path / "lib.scad").as_uri()


async def test_completion(client: LanguageClient, tmp_path):
    text = "include <>\nmodule m(size, height = 2) {\n    cube(size);\n    \n}\nm(size = 1, );\n"
    (tmp_path / "lib.scad").write_text(LIBRARY)
    uri = open_document(client, tmp_path / "main.qcsg", text)

    async def labels(needle, shift):
        result = await client.text_document_completion_async(
            types.CompletionParams(**(at(uri, text, needle, 0, shift)))
        )
        items = result.items if hasattr(result, "items") else result
        return {item.label: item for item in items}

    inside = await labels("    \n", 4)
    assert "size" in inside and "height" in inside
    assert inside["cylinder"].detail.startswith("cylinder(h, r1, r2")
    named = await labels(", )", 2)
    assert "height =" in named and "size =" not in named
    paths = await labels("<>", 1)
    assert "lib.scad" in paths and "main.qcsg" not in paths


async def test_signature_help(client: LanguageClient, tmp_path):
    text = "cylinder(10, 2, );\n"
    uri = open_document(client, tmp_path / "s.qcsg", text)
    help = await client.text_document_signature_help_async(types.SignatureHelpParams(**(at(uri, text, ", )", 0, 2))))
    assert help.signatures[0].label.startswith("cylinder(h, r1, r2")
    assert help.active_parameter == 2


async def test_semantic_tokens(client: LanguageClient, tmp_path):
    text = "module m(p) cube(p); // note\n$fn = 8;\nm(1);\n"
    uri = open_document(client, tmp_path / "t.qcsg", text)
    legend = client.server_capabilities.semantic_tokens_provider.legend
    result = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=doc(uri)))
    data = result.data
    assert len(data) % 5 == 0
    tokens, line, start = {}, 0, 0
    for i in range(0, len(data), 5):
        delta_line, delta_start, length, kind, modifiers = data[i : i + 5]
        line += delta_line
        start = start + delta_start if delta_line == 0 else delta_start
        names = [m for bit, m in enumerate(legend.token_modifiers) if modifiers >> bit & 1]
        tokens[(line, start)] = (legend.token_types[kind], length, names)

    def token(needle):
        position = position_of(text, needle)
        return tokens[(position.line, position.character)]

    assert token("module")[0] == "keyword"
    assert token("m(p)")[0] == "macro" and "declaration" in token("m(p)")[2]
    assert token("p)")[0] == "parameter"
    assert token("cube")[0] == "macro" and "defaultLibrary" in token("cube")[2]
    assert token("// note")[0] == "comment"
    assert token("$fn")[0] == "specialVariable"
    assert token("8")[0] == "number"


async def test_inlay_hints(client: LanguageClient, tmp_path):
    text = "a = 2;\nb = a * 3 + 1;\ncylinder(b, 1);\n"
    uri = open_document(client, tmp_path / "i.qcsg", text)
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            text_document=doc(uri),
            range=types.Range(start=types.Position(line=0, character=0), end=types.Position(line=3, character=0)),
        )
    )
    assert [h.label for h in hints] == ["= 7", "h =", "r1 ="]


async def test_formatting(client: LanguageClient, tmp_path):
    text = "x=1;\nmodule m(a=1){\ncube(a);\n}\n"
    uri = open_document(client, tmp_path / "f.qcsg", text)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=doc(uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)
        )
    )
    assert len(edits) == 1
    assert edits[0].new_text == "x = 1;\nmodule m(a = 1) {\n    cube(a);\n}\n"
    broken = open_document(client, tmp_path / "g.qcsg", "x = ;\n")
    refused = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=doc(broken), options=types.FormattingOptions(tab_size=4, insert_spaces=True)
        )
    )
    assert not refused


async def test_folding_ranges(client: LanguageClient, tmp_path):
    text = "// one\n// two\nmodule m() {\n    cube(1);\n}\n"
    uri = open_document(client, tmp_path / "r.qcsg", text)
    ranges = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=doc(uri)))
    assert {(r.start_line, r.end_line, r.kind) for r in ranges} >= {
        (0, 1, types.FoldingRangeKind.Comment),
        (2, 3, types.FoldingRangeKind.Region),
    }


async def test_code_actions(client: LanguageClient, tmp_path):
    text = "width = 1;\ncube(widht);\nspare = 2;\ncube(depth);\n"
    uri = open_document(client, tmp_path / "q.qcsg", text)
    diagnostics = await diagnostics_until(client, uri, lambda d: len(d) > 0)
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc(uri),
            range=types.Range(start=types.Position(line=0, character=0), end=types.Position(line=4, character=0)),
            context=types.CodeActionContext(diagnostics=diagnostics),
        )
    )
    titles = {a.title: a for a in actions}
    fix = titles["Change `widht` to `width`"]
    assert fix.is_preferred
    assert fix.edit.changes[uri][0].new_text == "width"
    assert "Declare `depth`" in titles and "Remove unused `spare`" in titles


async def test_requests_interleaved_with_changes(client: LanguageClient, tmp_path):
    """Edits and requests in flight together: the server stays consistent and alive."""
    text = "size = 1;\ncube(size);\n"
    uri = open_document(client, tmp_path / "busy.qcsg", text)
    pending = []
    current = text
    for version in range(2, 40):
        # Append one statement per version, at the end of the document.
        line = current.count("\n")
        addition = f"v{version} = size + {version};\necho(v{version});\n"
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                content_changes=[
                    types.TextDocumentContentChangePartial(
                        range=types.Range(start=types.Position(line=line, character=0), end=types.Position(line=line, character=0)),
                        text=addition,
                    )
                ],
            )
        )
        current += addition
        pending.append(client.text_document_hover_async(types.HoverParams(**(at(uri, text, "size", 1)))))
        pending.append(client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=doc(uri))))
    results = await asyncio.gather(*pending, return_exceptions=True)
    # A request may be answered for an older version, but never fail.
    assert not [r for r in results if isinstance(r, Exception)], results
    # Only the echo output of the last version remains: one line per `echo`.
    echoes = await diagnostics_until(
        client, uri, lambda d: len(d) == 38 and all(x.severity == types.DiagnosticSeverity.Information for x in d)
    )
    assert echoes[-1].message == "ECHO: 40"
    final = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=doc(uri)))
    assert len(final) == 1 + 38
    assert final[-1].name == "v39"


async def test_typing_a_file_character_by_character(client: LanguageClient, tmp_path):
    """Every prefix of a program is a broken file; the server answers them all."""
    program = 'module ring(r = 2) { difference() { cylinder(h = 1, r = r); cylinder(h = 3, r = r - 1); } }\nring(r = 5);\n'
    uri = open_document(client, tmp_path / "typing.qcsg", "")
    for i, char in enumerate(program):
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=i + 2),
                content_changes=[types.TextDocumentContentChangeWholeDocument(text=program[: i + 1])],
            )
        )
        if i % 7 == 0:
            end = position_of(program[: i + 1] + "\0", "\0")
            await client.text_document_completion_async(
                types.CompletionParams(text_document=doc(uri), position=end)
            )
            await client.text_document_hover_async(types.HoverParams(text_document=doc(uri), position=end))
    await diagnostics_until(client, uri, lambda d: len(d) == 0)


async def test_hover_shows_the_quadrics_of_a_call(client: LanguageClient, tmp_path):
    text = "module post(h) cylinder(h = h, r = 1);\nfor (i = [0 : 3]) translate([5 * i, 0, 0]) post(2);\nsphere(r = 4);\n"
    uri = open_document(client, tmp_path / "geometry.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    sphere = await client.text_document_hover_async(types.HoverParams(**(at(uri, text, "sphere"))))
    value = sphere.contents.value
    assert "built-in primitive" in value, value
    assert "**geometry**: 1 instance · 1 quadric" in value, value
    assert "**sphere** · centre (0, 0, 0) · radius 4" in value, value
    post = await client.text_document_hover_async(types.HoverParams(**(at(uri, text, "post", 1))))
    value = post.contents.value
    assert "module post(h)" in value, value
    assert "4 instances" in value and "instance 3:" in value and "… and 1 more instance" in value, value
    assert "centre (10, 0, 1)" in value, value
    # A name that is not a module instantiation evaluates nothing and shows no geometry.
    h = await client.text_document_hover_async(types.HoverParams(**(at(uri, text, "h", 2))))
    assert "geometry" not in h.contents.value


async def test_evaluation_diagnostics(client: LanguageClient, tmp_path):
    text = 'echo("size", 2 * 3);\nassert(1 > 2, "too small");\n'
    uri = open_document(client, tmp_path / "runtime.qcsg", text)
    diagnostics = await diagnostics_until(client, uri, lambda d: len(d) >= 2)
    echo = next(d for d in diagnostics if d.severity == types.DiagnosticSeverity.Information)
    assert echo.message == 'ECHO: "size", 6'
    assert echo.range.start == position_of(text, "echo")
    failed = next(d for d in diagnostics if d.severity == types.DiagnosticSeverity.Error)
    assert "too small" in failed.message and failed.range.start.line == 1


async def test_errors_of_included_files(client: LanguageClient, tmp_path):
    (tmp_path / "broken.scad").write_text("module part() cube(1);\nx = ;\n")
    (tmp_path / "checks.scad").write_text('module check(n) assert(n < 3, "n too big");\n')
    text = "include <broken.scad>\nuse <checks.scad>\npart();\n"
    uri = open_document(client, tmp_path / "main.qcsg", text)
    diagnostics = await diagnostics_until(client, uri, lambda d: len(d) > 0)
    shown = next(d for d in diagnostics if d.severity == types.DiagnosticSeverity.Error)
    assert shown.range.start == position_of(text, "<broken.scad>")
    assert shown.message.startswith("in included file `broken.scad`")
    inside = shown.related_information[0].location
    assert inside.uri == (tmp_path / "broken.scad").as_uri() and inside.range.start.line == 1

    # A runtime error inside a used file, fine on its own: shown at the `use` line, and in that
    # file once it is open.
    fixed = "include <broken.scad>\nuse <checks.scad>\ncheck(5);\n".replace("include <broken.scad>\n", "")
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=fixed)],
        )
    )
    at_use = await diagnostics_until(client, uri, lambda d: any("n too big" in x.message for x in d))
    assert next(d for d in at_use if "n too big" in d.message).range.start == position_of(fixed, "<checks.scad>")
    checks_text = (tmp_path / "checks.scad").read_text()
    checks = open_document(client, tmp_path / "checks.scad", checks_text)
    in_file = await diagnostics_until(client, checks, lambda d: any("n too big" in x.message for x in d))
    assert next(d for d in in_file if "n too big" in d.message).range.start == position_of(checks_text, "assert")

    # Fixing the library in the editor re-checks the program that uses it.
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=checks, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text="module check(n) cube(n);\n")],
        )
    )
    await diagnostics_until(client, uri, lambda d: len(d) == 0)
    # Only the library's own warning (its module is unused on its own) remains.
    left = await diagnostics_until(client, checks, lambda d: not any("n too big" in x.message for x in d))
    assert [d.code for d in left] == ["W0103"]
