"""The editor reports what `qcsg check` reports, up to the normal form: an unbounded solid, found
only when the DNF is built, reaches the editor with the code, message and range of `check`."""

import json
import subprocess

from lsprotocol import types
from pytest_lsp import LanguageClient

from conftest import QCSG, diagnostics_until, open_document

UNBOUNDED = "union() { sphere(3); halfspace([0, 0, 1], 0); }\n"


def check_json(path):
    """`qcsg check --format json` of a file: its diagnostics as (code, message, start, end), the
    message followed by its help as the editor shows it."""
    run = subprocess.run([QCSG, "check", "--format", "json", str(path)], capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    return [
        (d["code"], d["message"] + (f"\nhelp: {d['help']}" if d["help"] else ""), (d["range"]["start"]["line"], d["range"]["start"]["character"]),
         (d["range"]["end"]["line"], d["range"]["end"]["character"]))
        for d in json.loads(run.stdout)
    ]


async def test_an_unbounded_solid_is_reported_as_check_reports_it(client: LanguageClient, tmp_path):
    path = tmp_path / "unbounded.qcsg"
    path.write_text(UNBOUNDED)
    uri = open_document(client, path, UNBOUNDED)
    published = await diagnostics_until(client, uri, lambda d: any(x.code == "E0600" for x in d))
    editor = [
        (d.code, d.message, (d.range.start.line, d.range.start.character),
         (d.range.end.line, d.range.end.character))
        for d in published
        if d.severity == types.DiagnosticSeverity.Error
    ]
    assert editor == check_json(path)
