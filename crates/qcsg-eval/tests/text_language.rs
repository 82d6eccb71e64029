//! `text()`'s `language` is a BCP 47 tag, ASCII; any other string is no language, not a panic
//! (rustybuzz's tag parser sliced a non-ASCII string inside a character, found by fuzzing).

mod common;

use common::eval;

#[test]
fn a_non_ascii_language_is_no_language() {
    for language in ["chr([12, 58, 10])", "\"é\"", "\"zh-漢\"", "\"\\u{202c}x\""] {
        let e = eval(&format!("text(\"ab\", language = {language});"));
        assert!(!e.has_errors(), "{language}: {:?}", e.diagnostics);
    }
    // The fuzzer's input, as found.
    let e = eval(
        "color(chr(8)){text(\"\u{202c}\",valign=\"\",direction=\"\",language=chr((ceil((let(l5=12.1)l5))*[6,ceil(58),10])),script=chr($));}",
    );
    drop(e);
}
