"""Argument-name completion through `qcsg lsp`: names first, with defaults and docs, and edits
that replace what was typed, also in unfinished text."""

from lsprotocol import types
from pytest_lsp import LanguageClient

from conftest import diagnostics_until, open_document, position_of

LIBRARY = "/// A flat ring.\n/// `outer`: the outer radius\nmodule washer(outer = 10, inner = 4) cylinder(h = 1, r = outer);\n"


async def complete(client: LanguageClient, uri: str, text: str, needle: str, shift: int):
    """The completion items at `needle` plus `shift` characters, in the client's order."""
    result = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=position_of(text, needle, 0, shift),
        )
    )
    items = result.items if hasattr(result, "items") else result
    return sorted(items, key=lambda item: item.sort_text or item.label)


def apply(text: str, edit: types.TextEdit) -> str:
    """`text` with a one-line edit applied (ASCII text: columns are characters)."""
    lines = text.split("\n")
    start, end = edit.range.start, edit.range.end
    assert start.line == end.line
    line = lines[start.line]
    lines[start.line] = line[: start.character] + edit.new_text + line[end.character :]
    return "\n".join(lines)


async def test_builtin_parameters_come_first_in_an_unfinished_call(client: LanguageClient, tmp_path):
    text = "sphere(r"
    uri = open_document(client, tmp_path / "a.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    items = await complete(client, uri, text, "(r", 2)
    first = items[0]
    assert first.label == "r ="
    assert first.kind == types.CompletionItemKind.Property
    assert first.detail == "a number · default 1"
    assert "a ball" in first.documentation.value
    assert apply(text, first.text_edit) == "sphere(r = "
    labels = [item.label for item in items]
    assert "round" in labels and "rotate" not in labels


async def test_used_module_names_skip_given_ones(client: LanguageClient, tmp_path):
    (tmp_path / "lib.scad").write_text(LIBRARY)
    text = "use <lib.scad>\nwasher(inner = 3, );\n"
    uri = open_document(client, tmp_path / "main.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    items = await complete(client, uri, text, ", )", 2)
    names = [item.label for item in items if item.kind == types.CompletionItemKind.Property]
    assert names[0] == "outer =" and "inner =" not in names and "$fn =" in names
    outer = items[0]
    assert outer.detail == "default 10"
    assert "`outer`: the outer radius" in outer.documentation.value
    # Expressions follow the names.
    assert any(item.label == "PI" for item in items[len(names) :])


async def test_special_variable_replaces_the_typed_dollar(client: LanguageClient, tmp_path):
    text = "cube(1, $"
    uri = open_document(client, tmp_path / "b.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    items = await complete(client, uri, text, "$", 1)
    fn = next(item for item in items if item.label == "$fn =")
    assert apply(text, fn.text_edit) == "cube(1, $fn = "


async def test_values_get_no_names(client: LanguageClient, tmp_path):
    text = "function grow(p, by = 2) = p * by;\nx = grow(by = );\ny = grow();\n"
    uri = open_document(client, tmp_path / "c.qcsg", text)
    await diagnostics_until(client, uri, lambda d: True)
    items = await complete(client, uri, text, "by = )", 5)
    assert not [item for item in items if item.kind == types.CompletionItemKind.Property]
    names = await complete(client, uri, text, "grow()", 5)
    assert [item.label for item in names[:2]] == ["p =", "by ="]
