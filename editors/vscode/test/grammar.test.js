// Checks the TextMate grammar against the language itself: the keyword list against the lexer
// (crates/qcsg-syntax/src/lexer.rs) and grammar/qcsg.ebnf, the built-in names against
// crates/qcsg-sema/src/builtins.rs, the scope of each token class on sample lines, and that every
// .qcsg/.scad file under examples/ and tests/ tokenizes and leaves no rule open.
// Run with `npm test` (node --test).
"use strict";

const assert = require("node:assert/strict");
const fs = require("node:fs");
const path = require("node:path");
const { test, before } = require("node:test");
const vsctm = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const root = path.resolve(__dirname, "..", "..", "..");
const grammarPath = path.join(__dirname, "..", "syntaxes", "qcsg.tmLanguage.json");
const grammarJson = JSON.parse(fs.readFileSync(grammarPath, "utf8"));
const read = (rel) => fs.readFileSync(path.join(root, rel), "utf8");

let grammar;

before(async () => {
  const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (sources) => new oniguruma.OnigScanner(sources),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scopeName) =>
      scopeName === "source.qcsg"
        ? vsctm.parseRawGrammar(fs.readFileSync(grammarPath, "utf8"), grammarPath)
        : null,
  });
  grammar = await registry.loadGrammar("source.qcsg");
});

/** Tokenizes `text` from the initial state: a list of {line, text, scopes}, and the final state. */
function tokenize(text) {
  let state = vsctm.INITIAL;
  const tokens = [];
  text.split(/\r?\n/).forEach((line, lineNo) => {
    const result = grammar.tokenizeLine(line, state, 5000);
    assert.ok(!result.stoppedEarly, `tokenizing stopped early on line ${lineNo + 1}: ${line}`);
    for (const t of result.tokens) {
      tokens.push({ line: lineNo, text: line.slice(t.startIndex, t.endIndex), scopes: t.scopes });
    }
    state = result.ruleStack;
  });
  return { tokens, state };
}

/** The words of a `\b(a|b|c)\b` match. */
function words(match) {
  const m = /^\\b\(([A-Za-z0-9_|]+)\)(\\b|\\s\*\(\?=\\\(\))$/.exec(match);
  assert.ok(m, `unexpected word-list pattern ${match}`);
  return m[1].split("|");
}

const repo = grammarJson.repository;
const keywordRules = [...repo.keywords.patterns, ...repo.constants.patterns];
const reservedWords = keywordRules.flatMap((r) => words(r.match));
const specialFormWords = words(repo["special-forms"].match);
const moduleWords = words(repo["builtin-module-calls"].match);
const functionWords = words(repo["builtin-function-calls"].match);

/** The words the lexer turns into their own tokens (`#[token("module")]` and so on). */
function lexerWords() {
  const src = read("crates/qcsg-syntax/src/lexer.rs");
  return [...src.matchAll(/#\[token\("([A-Za-z_]+)"\)\]/g)].map((m) => m[1]);
}

/** The alternatives of the `Keyword` production of grammar/qcsg.ebnf. */
function ebnfKeywords() {
  const src = read("grammar/qcsg.ebnf");
  const m = /^Keyword\s*::=((?:\s*\|?\s*'[a-z]+')+)/m.exec(src);
  assert.ok(m, "no Keyword production in grammar/qcsg.ebnf");
  return [...m[1].matchAll(/'([a-z]+)'/g)].map((x) => x[1]);
}

/** The names in the `pub const NAME: &[...] = &[ ... ];` table of builtins.rs. */
function builtinTable(name) {
  const src = read("crates/qcsg-sema/src/builtins.rs");
  const start = src.indexOf(`pub const ${name}:`);
  assert.ok(start >= 0, `no ${name} in builtins.rs`);
  const end = src.indexOf("\n];", start);
  const body = src.slice(start, end);
  const names = [
    // Entries are indented by four spaces: `Struct {` with `name: "…"` inside, `ctor("…", …)`,
    // or a tuple `("…", …)` (rustfmt may break it after the parenthesis).
    ...body.matchAll(/^ {8}name: "([^"]+)"/gm),
    ...body.matchAll(/^ {4}[a-z_]+\("([^"]+)"/gm),
    ...body.matchAll(/^ {4}\(\s*"([^"]+)"/gm),
  ].map((m) => m[1]);
  assert.ok(names.length > 0, `no names parsed from ${name}`);
  return names;
}

const sorted = (xs) => [...new Set(xs)].sort();

/** Asserts that the token of `snippet` whose text is `text` (the nth such) has `scope`. */
function expectScope(snippet, text, scope, nth = 0) {
  const hits = tokenize(snippet).tokens.filter((t) => t.text === text);
  assert.ok(hits.length > nth, `no token ${JSON.stringify(text)} in ${JSON.stringify(snippet)}`);
  const scopes = hits[nth].scopes;
  assert.ok(
    scopes.includes(scope),
    `${JSON.stringify(text)} in ${JSON.stringify(snippet)}: expected ${scope}, got ${scopes.join(" ")}`,
  );
}

test("keywords equal the lexer's and the EBNF's", () => {
  // Every word token of the lexer is highlighted: reserved words as keywords or constants,
  // `assert` and `echo` (names with a special expression form) as built-ins.
  assert.deepEqual(sorted([...reservedWords, ...specialFormWords]), sorted(lexerWords()));
  assert.deepEqual(sorted(reservedWords), sorted(ebnfKeywords()));
});

test("built-in names equal builtins.rs", () => {
  const modules = builtinTable("MODULES").filter((n) => !specialFormWords.includes(n));
  assert.deepEqual(sorted(moduleWords), sorted(modules));
  assert.deepEqual(sorted(functionWords), sorted(builtinTable("FUNCTIONS")));
});

test("every keyword gets its scope", () => {
  const expected = {
    module: ["module m() cube(1);", "storage.type.module.qcsg"],
    function: ["function f(x) = x;", "storage.type.function.qcsg"],
    if: ["if (a) cube(1); else sphere(1);", "keyword.control.qcsg"],
    else: ["if (a) cube(1); else sphere(1);", "keyword.control.qcsg"],
    for: ["for (i = [0:3]) cube(i);", "keyword.control.qcsg"],
    let: ["let (a = 1) cube(a);", "keyword.control.qcsg"],
    each: ["v = [each [1, 2]];", "keyword.control.qcsg"],
    true: ["c = true;", "constant.language.boolean.qcsg"],
    false: ["c = false;", "constant.language.boolean.qcsg"],
    undef: ["c = undef;", "constant.language.undef.qcsg"],
    include: ["include <lib/shapes.scad>", "keyword.control.import.qcsg"],
    use: ["use <lib/shapes.scad>", "keyword.control.import.qcsg"],
    assert: ["assert(x > 0) cube(x);", "support.function.builtin.qcsg"],
    echo: ["v = echo(\"v\", 1) 1;", "support.function.builtin.qcsg"],
  };
  for (const word of lexerWords()) {
    assert.ok(expected[word], `no sample line for the keyword ${word}`);
    const [line, scope] = expected[word];
    expectScope(line, word, scope);
  }
});

test("every built-in module and function call gets its scope", () => {
  for (const name of moduleWords) {
    expectScope(`${name}(1) cube(1);`, name, "support.function.module.qcsg");
    expectScope(`translate([0, 0, 1]) ${name}();`, name, "support.function.module.qcsg");
  }
  for (const name of functionWords) {
    expectScope(`x = ${name}(1, 2);`, name, "support.function.builtin.qcsg");
    expectScope(`cube(${name} (1));`, name, "support.function.builtin.qcsg");
  }
  for (const name of builtinTable("SPECIAL_VARIABLES")) {
    expectScope(`sphere(1, ${name} = 8);`, name, "variable.language.special.qcsg");
  }
});

test("token classes get their scopes", () => {
  const cases = [
    // Comments, doc comments.
    ["// plain", "// plain", "comment.line.double-slash.qcsg", "//"],
    ["/// doc", " doc", "comment.line.triple-slash.documentation.qcsg"],
    ["//// not doc", "//// not doc", "comment.line.double-slash.qcsg", "//"],
    ["/* block */ x = 1;", " block ", "comment.block.qcsg"],
    ["/** doc */ x = 1;", " doc ", "comment.block.documentation.qcsg"],
    ["/**/ x = 1;", "/*", "comment.block.qcsg"],
    ["/*** banner ***/", "** banner **", "comment.block.qcsg"],
    ["/*\n multi\n*/ cube(1);", " multi", "comment.block.qcsg"],
    ["/**\n * doc\n */\nmodule m() cube(1);", " * doc", "comment.block.documentation.qcsg"],
    // Strings and escapes.
    ['s = "a\\"b";', "a", "string.quoted.double.qcsg"],
    ['s = "a\\"b";', '\\"', "constant.character.escape.qcsg"],
    ['s = "\\\\ \\n \\t \\r";', "\\\\", "constant.character.escape.qcsg"],
    ['s = "\\\\ \\n \\t \\r";', "\\n", "constant.character.escape.qcsg"],
    ['s = "\\x41";', "\\x41", "constant.character.escape.qcsg"],
    ['s = "\\u263A";', "\\u263A", "constant.character.escape.qcsg"],
    ['s = "\\q";', "\\q", "invalid.illegal.unknown-escape.qcsg"],
    ['s = "a // b";', "a // b", "string.quoted.double.qcsg"],
    // Numbers.
    ["x = 1;", "1", "constant.numeric.qcsg"],
    ["x = 1.5;", "1.5", "constant.numeric.qcsg"],
    ["x = .5;", ".5", "constant.numeric.qcsg"],
    ["x = 1.;", "1.", "constant.numeric.qcsg"],
    ["x = 1e-3;", "1e-3", "constant.numeric.qcsg"],
    ["x = 2.5E+4;", "2.5E+4", "constant.numeric.qcsg"],
    ["x = a1;", "a1", "variable.other.qcsg"],
    // Special and built-in variables, identifiers.
    ["$fn = 64;", "$fn", "variable.language.special.qcsg"],
    ["x = $children;", "$children", "variable.language.special.qcsg"],
    ["x = 2 * PI;", "PI", "support.constant.qcsg"],
    ["width = 3;", "width", "variable.other.assignment.qcsg"],
    ["x = width + 1;", "width", "variable.other.qcsg"],
    // Operators.
    ["x = a + b - c * d / e % f ^ g;", "+", "keyword.operator.arithmetic.qcsg"],
    ["x = a + b - c * d / e % f ^ g;", "%", "keyword.operator.arithmetic.qcsg"],
    ["x = a + b - c * d / e % f ^ g;", "^", "keyword.operator.arithmetic.qcsg"],
    ["x = a < b && c >= d || !e;", "<", "keyword.operator.comparison.qcsg"],
    ["x = a < b && c >= d || !e;", ">=", "keyword.operator.comparison.qcsg"],
    ["x = a == b != c <= d;", "==", "keyword.operator.comparison.qcsg"],
    ["x = a == b != c <= d;", "!=", "keyword.operator.comparison.qcsg"],
    ["x = a < b && c >= d || !e;", "&&", "keyword.operator.logical.qcsg"],
    ["x = a < b && c >= d || !e;", "||", "keyword.operator.logical.qcsg"],
    ["x = a < b && c >= d || !e;", "!", "keyword.operator.logical.qcsg"],
    ["x = a ? b : c;", "?", "keyword.operator.ternary.qcsg"],
    ["x = [0 : 2 : 10];", ":", "punctuation.separator.colon.qcsg"],
    ["x = p.x;", ".", "punctuation.accessor.qcsg"],
    ["x = 1;", "=", "keyword.operator.assignment.qcsg"],
    ["cube(size = 2);", "=", "keyword.operator.assignment.qcsg"],
    ["cube(size = 2);", ";", "punctuation.terminator.statement.qcsg"],
    ["x = 1;", ";", "punctuation.terminator.statement.qcsg"],
    ["cube([1, 2, 3]);", ",", "punctuation.separator.comma.qcsg"],
    // Modifiers before statements, but operators inside expressions.
    ["* sphere(1);", "*", "keyword.other.modifier.qcsg"],
    ["!cube(1);", "!", "keyword.other.modifier.qcsg"],
    ["#translate([1, 0, 0]) cube(1);", "#", "keyword.other.modifier.qcsg"],
    ["%cylinder(h = 1, r = 2);", "%", "keyword.other.modifier.qcsg"],
    ["difference() { cube(2); #sphere(1); }", "#", "keyword.other.modifier.qcsg"],
    ["translate([1, 0, 0]) %sphere(1);", "%", "keyword.other.modifier.qcsg"],
    ["if (a) !cube(1);", "!", "keyword.other.modifier.qcsg"],
    ["cube(a * 2);", "*", "keyword.operator.arithmetic.qcsg"],
    ["x = a % b(1);", "%", "keyword.operator.arithmetic.qcsg"],
    ["function f(a) = !a;", "!", "keyword.operator.logical.qcsg"],
    // Definitions and calls.
    ["module wheel(r = 1) cylinder(h = 1, r = r);", "wheel", "entity.name.function.module.qcsg"],
    ["function area(r) = PI * r * r;", "area", "entity.name.function.qcsg"],
    ["wheel(2);", "wheel", "entity.name.function.call.qcsg"],
    ["x = area(2);", "area", "entity.name.function.call.qcsg"],
    ["f = function (x) x * 2;", "function", "storage.type.function.qcsg"],
    ["x = sin(30) + max([1, 2]);", "sin", "support.function.builtin.qcsg"],
    ["x = sin(30) + max([1, 2]);", "max", "support.function.builtin.qcsg"],
    ["translate([1, 0, 0]) sphere(r = 2);", "translate", "support.function.module.qcsg"],
    ["translate([1, 0, 0]) sphere(r = 2);", "sphere", "support.function.module.qcsg"],
    ["cube = 3;", "cube", "variable.other.assignment.qcsg"],
    // include/use paths.
    ["include <lib/shapes.scad>", "lib/shapes.scad", "string.quoted.other.lt-gt.include.qcsg"],
    ["use <tools.scad>", "<", "punctuation.definition.string.begin.qcsg"],
    ["use <tools.scad>", ">", "punctuation.definition.string.end.qcsg"],
    ["x = a <b> c;", "<", "keyword.operator.comparison.qcsg"],
  ];
  for (const [snippet, text, scope, tokenText] of cases) {
    expectScope(snippet, tokenText ?? text, scope);
  }
});

/** Every .qcsg and .scad file under `dir` (relative to the repository root). */
function sources(dir) {
  const out = [];
  const walk = (rel) => {
    for (const entry of fs.readdirSync(path.join(root, rel), { withFileTypes: true })) {
      const child = path.join(rel, entry.name);
      if (entry.isDirectory()) walk(child);
      else if (/\.(qcsg|scad)$/.test(entry.name)) out.push(child);
    }
  };
  walk(dir);
  return out.sort();
}

test("every example and test source tokenizes and closes its rules", () => {
  const files = [...sources("examples"), ...sources("tests")];
  assert.ok(files.length > 0, "no .qcsg/.scad files found");
  const keywordScopes = new Map([
    ...keywordRules.flatMap((r) => words(r.match).map((w) => [w, r.name])),
    ...specialFormWords.map((w) => [w, repo["special-forms"].name]),
  ]);
  for (const file of files) {
    const text = read(file);
    const { tokens, state } = tokenize(text);
    // Outside comments and strings a keyword always gets its keyword scope.
    for (const t of tokens) {
      const word = t.text.trim();
      if (!keywordScopes.has(word)) continue;
      if (t.scopes.some((s) => /^(comment|string)\./.test(s))) continue;
      assert.ok(
        t.scopes.includes(keywordScopes.get(word)) ||
          (word === "module" && t.scopes.includes("storage.type.module.qcsg")) ||
          (word === "function" && t.scopes.includes("storage.type.function.qcsg")),
        `${file}:${t.line + 1}: ${word} has ${t.scopes.join(" ")}`,
      );
    }
    // Files without syntax errors leave no comment, string or bracket open at the end.
    if (file.startsWith(path.join("tests", "check", "syntax"))) continue;
    const after = grammar.tokenizeLine("end_of_file = 1;", state).tokens[0];
    assert.deepEqual(
      after.scopes,
      ["source.qcsg", "meta.assignment.qcsg", "variable.other.assignment.qcsg"],
      `${file}: a rule is still open at the end of the file`,
    );
  }
});
