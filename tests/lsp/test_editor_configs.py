"""The Helix configuration against Helix's schema for `languages.toml`.

Helix itself is not installed where the tests run, so this checks the file the way Helix's
loader reads it: `[[language]]` tables deny unknown keys, a new language needs `scope` and
`file-types`, `tab-width` is 1 to 16, block comment tokens are `{start, end}` tables, every
named language server is configured, and the query files that inherit from the OpenSCAD grammar
exist. The key list follows `LanguageConfiguration` in helix-core (`syntax/config.rs`, 25.07).
"""

import pathlib
import tomllib

HELIX = pathlib.Path(__file__).resolve().parents[2] / "editors" / "helix"

LANGUAGE_KEYS = {
    "name", "language-id", "scope", "file-types", "shebangs", "roots", "comment-token",
    "comment-tokens", "block-comment-tokens", "text-width", "soft-wrap", "auto-format",
    "formatter", "path-completion", "word-completion", "diagnostic-severity", "grammar",
    "injection-regex", "language-servers", "indent", "debugger", "auto-pairs", "rulers",
    "workspace-lsp-roots", "persistent-diagnostic-sources", "rainbow-brackets",
}
SERVER_KEYS = {"command", "args", "environment", "config", "timeout", "required-root-patterns"}
# Languages Helix ships, which a user file may extend with a partial table (merged by name).
BUILT_IN = {"openscad"}


def load():
    return tomllib.loads((HELIX / "languages.toml").read_text())


def test_language_tables_follow_the_schema():
    config = load()
    servers = config.get("language-server", {})
    assert set(config) <= {"language", "language-server", "use-grammars"}
    for language in config["language"]:
        unknown = set(language) - LANGUAGE_KEYS
        assert not unknown, f"{language['name']}: unknown keys {unknown}"
        if language["name"] not in BUILT_IN:
            assert isinstance(language["scope"], str) and language["scope"]
            assert all(isinstance(t, str) for t in language["file-types"])
        indent = language.get("indent")
        if indent is not None:
            assert set(indent) == {"tab-width", "unit"} and 1 <= indent["tab-width"] <= 16
        for token in language.get("block-comment-tokens", []):
            assert set(token) == {"start", "end"}
        comment = language.get("comment-tokens", [])
        assert isinstance(comment, (str, list))
        for server in language.get("language-servers", []):
            name = server if isinstance(server, str) else server["name"]
            assert name in servers, f"language server {name} is not configured"
        formatter = language.get("formatter")
        if formatter is not None:
            assert set(formatter) <= {"command", "args"} and isinstance(formatter["command"], str)


def test_language_server_runs_qcsg_lsp():
    servers = load()["language-server"]
    for name, server in servers.items():
        assert set(server) <= SERVER_KEYS, f"{name}: unknown keys {set(server) - SERVER_KEYS}"
    assert servers["qcsg"]["command"] == "qcsg" and servers["qcsg"]["args"] == ["lsp"]


def test_qcsg_files_are_served_and_highlighted():
    languages = {language["name"]: language for language in load()["language"]}
    qcsg = languages["qcsg"]
    assert "qcsg" in qcsg["file-types"] and "qcsg" in qcsg["language-servers"]
    assert "qcsg" in languages["openscad"]["language-servers"]
    queries = HELIX / "runtime" / "queries" / "qcsg"
    for name in ("highlights.scm", "indents.scm"):
        text = (queries / name).read_text()
        assert "; inherits: openscad" in text, name
