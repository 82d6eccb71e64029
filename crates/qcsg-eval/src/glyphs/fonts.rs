//! Finding a font as OpenSCAD does: a fontconfig-style name (`"Liberation Sans:style=Bold"`)
//! matched against the fonts of the system's font folders, with Liberation Sans bundled so that
//! `text()` works where no font is installed.
//!
//! The folders are scanned once per process (their files' name tables only), at most
//! [`MAX_FONT_FILES`] files. A family matches ignoring case and spaces, as fontconfig compares
//! family names; without a `style` the regular face is preferred.

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// Liberation Sans Regular, the default font of OpenSCAD (licence beside it in `fonts/`).
pub const BUNDLED_SANS: &[u8] = include_bytes!("../../fonts/LiberationSans-Regular.ttf");

/// The family used when `font` is not given, as in OpenSCAD.
pub const DEFAULT_FAMILY: &str = "Liberation Sans";

/// The most font files the folder scan reads.
const MAX_FONT_FILES: usize = 4096;

/// The most bytes of a font file that is read.
const MAX_FONT_BYTES: u64 = 64 << 20;

/// A face found for a name.
#[derive(Clone)]
pub struct FoundFont {
    /// The font file's bytes.
    pub data: Arc<Vec<u8>>,
    /// The face's index in a collection.
    pub index: u32,
    /// The family and style, for messages.
    pub family: String,
    /// The face's style name.
    pub style: String,
}

/// One face of the scan.
#[derive(Clone)]
struct Entry {
    path: Option<PathBuf>,
    index: u32,
    family: String,
    style: String,
}

/// A fontconfig-style name: families (comma-separated) and an optional style.
#[derive(Debug, PartialEq)]
pub struct FontName {
    /// The families in order of preference.
    pub families: Vec<String>,
    /// The `style=` property, if any.
    pub style: Option<String>,
}

/// Parses `"Family, Other:style=Bold Italic:weight=…"`; properties other than `style` are
/// ignored.
pub fn parse_name(name: &str) -> FontName {
    let mut parts = name.split(':');
    let families = parts
        .next()
        .unwrap_or("")
        .split(',')
        .map(|f| f.trim().to_string())
        .filter(|f| !f.is_empty())
        .collect();
    let mut style = None;
    for property in parts {
        if let Some((key, value)) = property.split_once('=')
            && key.trim().eq_ignore_ascii_case("style")
        {
            style = Some(value.trim().to_string());
        }
    }
    FontName { families, style }
}

/// Lower case without spaces, hyphens or underscores, as fontconfig compares names.
fn folded(s: &str) -> String {
    s.chars()
        .filter(|c| !matches!(c, ' ' | '-' | '_'))
        .flat_map(char::to_lowercase)
        .collect()
}

/// The family and style names of a face: the typographic ones where present.
pub fn face_names(face: &ttf_parser::Face<'_>) -> (String, String) {
    let name = |ids: &[u16]| {
        ids.iter().find_map(|&id| {
            face.names()
                .into_iter()
                .filter(|n| n.name_id == id)
                .find_map(|n| n.to_string())
        })
    };
    (
        name(&[16, 1]).unwrap_or_default(),
        name(&[17, 2]).unwrap_or_default(),
    )
}

/// The faces of the system's font folders and the bundled font, scanned once.
fn catalogue() -> &'static Vec<Entry> {
    static CATALOGUE: OnceLock<Vec<Entry>> = OnceLock::new();
    CATALOGUE.get_or_init(|| {
        let mut folders: Vec<PathBuf> = vec![
            "/usr/share/fonts".into(),
            "/usr/local/share/fonts".into(),
            "/Library/Fonts".into(),
            "/System/Library/Fonts".into(),
            "C:\\Windows\\Fonts".into(),
        ];
        if let Some(home) = std::env::var_os("HOME") {
            let home = PathBuf::from(home);
            folders.push(home.join(".fonts"));
            folders.push(home.join(".local/share/fonts"));
        }
        let mut files = Vec::new();
        for folder in folders {
            collect_files(&folder, 0, &mut files);
        }
        files.sort();
        let mut entries = Vec::new();
        for path in files {
            let Ok(data) = read_font(&path) else { continue };
            let count = ttf_parser::fonts_in_collection(&data).unwrap_or(1);
            for index in 0..count.min(64) {
                if let Ok(face) = ttf_parser::Face::parse(&data, index) {
                    let (family, style) = face_names(&face);
                    entries.push(Entry {
                        path: Some(path.clone()),
                        index,
                        family,
                        style,
                    });
                }
            }
        }
        entries.push(Entry {
            path: None,
            index: 0,
            family: DEFAULT_FAMILY.into(),
            style: "Regular".into(),
        });
        entries
    })
}

fn read_font(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let mut data = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_FONT_BYTES)
        .read_to_end(&mut data)?;
    Ok(data)
}

/// The font files under `folder` (a few levels deep), up to [`MAX_FONT_FILES`].
fn collect_files(folder: &Path, depth: usize, files: &mut Vec<PathBuf>) {
    if depth > 6 || files.len() >= MAX_FONT_FILES {
        return;
    }
    let Ok(dir) = std::fs::read_dir(folder) else {
        return;
    };
    let mut children: Vec<PathBuf> = dir.filter_map(|e| e.ok().map(|e| e.path())).collect();
    children.sort();
    for path in children {
        if files.len() >= MAX_FONT_FILES {
            return;
        }
        if path.is_dir() {
            collect_files(&path, depth + 1, files);
        } else if path.extension().is_some_and(|e| {
            let e = e.to_string_lossy().to_ascii_lowercase();
            matches!(e.as_str(), "ttf" | "otf" | "ttc" | "otc")
        }) {
            files.push(path);
        }
    }
}

/// The faces of the font files a program registered with `use <file.ttf>`, searched before the
/// system's, as OpenSCAD adds such files to fontconfig's application fonts.
#[derive(Clone, Default)]
pub struct RegisteredFonts {
    faces: Vec<(Entry, Arc<Vec<u8>>)>,
}

/// Why a font file named by `use` cannot be registered.
#[derive(Debug)]
pub enum FontFileError {
    /// Reading it failed.
    Unreadable(std::io::Error),
    /// It is larger than the most bytes read of a font file.
    TooLarge,
    /// No face of it parses as a TrueType or OpenType font.
    NotAFont(String),
    /// Its faces draw with cubic (CFF) curves, which are not quadrics.
    Cubic(String),
}

impl std::fmt::Display for FontFileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Unreadable(e) => write!(f, "it cannot be read: {e}"),
            Self::TooLarge => write!(f, "it is larger than {} MiB", MAX_FONT_BYTES >> 20),
            Self::NotAFont(e) => write!(f, "it is not a TrueType or OpenType font ({e})"),
            Self::Cubic(family) => write!(
                f,
                "its font {family} draws its glyphs with cubic (CFF) curves, which are not \
                 quadrics; use a TrueType (.ttf) font"
            ),
        }
    }
}

impl RegisteredFonts {
    /// Reads the font file at `path` and registers its faces; the family names registered.
    pub fn register(&mut self, path: &Path) -> Result<Vec<String>, FontFileError> {
        let size = std::fs::metadata(path)
            .map_err(FontFileError::Unreadable)?
            .len();
        if size > MAX_FONT_BYTES {
            return Err(FontFileError::TooLarge);
        }
        let data = Arc::new(read_font(path).map_err(FontFileError::Unreadable)?);
        let count = ttf_parser::fonts_in_collection(&data).unwrap_or(1);
        let mut faces = Vec::new();
        let mut cubic = None;
        for index in 0..count.min(64) {
            let face = ttf_parser::Face::parse(&data, index)
                .map_err(|e| FontFileError::NotAFont(e.to_string()))?;
            let (family, style) = face_names(&face);
            if super::layout::is_cubic(&face) {
                cubic = Some(format!("{family} {style}"));
                continue;
            }
            faces.push(Entry {
                path: Some(path.to_path_buf()),
                index,
                family,
                style,
            });
        }
        if faces.is_empty() {
            return Err(match cubic {
                Some(name) => FontFileError::Cubic(name),
                None => FontFileError::NotAFont("it holds no face".into()),
            });
        }
        let families = faces.iter().map(|e| e.family.clone()).collect();
        self.faces
            .extend(faces.into_iter().map(|e| (e, Arc::clone(&data))));
        Ok(families)
    }
}

/// Whether a style name is a face's regular one.
fn is_regular(style: &str) -> bool {
    matches!(
        folded(style).as_str(),
        "regular" | "book" | "normal" | "roman" | "medium"
    )
}

/// The face `name` asks for, or `None` when no installed or bundled face has its family (the
/// caller falls back to the default font with a warning).
pub fn find(name: &FontName) -> Option<FoundFont> {
    find_with(name, &RegisteredFonts::default())
}

/// [`find`], searching the `registered` faces first. Each family is tried as written, then as
/// the families fontconfig substitutes for it ([`aliases`]).
pub fn find_with(name: &FontName, registered: &RegisteredFonts) -> Option<FoundFont> {
    let families: Vec<String> = if name.families.is_empty() {
        vec![DEFAULT_FAMILY.into()]
    } else {
        name.families.clone()
    };
    let families = families
        .iter()
        .flat_map(|f| std::iter::once(f.as_str()).chain(aliases(f).iter().copied()));
    let style = name.style.as_deref();
    for family in families {
        let entries = registered.faces.iter().map(|(e, _)| e);
        if let Some(chosen) = choose(entries, family, style) {
            let data = registered
                .faces
                .iter()
                .find(|(e, _)| std::ptr::eq(e, chosen))
                .map(|(_, d)| Arc::clone(d))?;
            return Some(FoundFont {
                data,
                index: chosen.index,
                family: chosen.family.clone(),
                style: chosen.style.clone(),
            });
        }
        if let Some(found) = choose(catalogue().iter(), family, style).and_then(load) {
            return Some(found);
        }
    }
    None
}

/// The families fontconfig's default configuration substitutes for `family` when it is not
/// installed (`30-metric-aliases.conf`, and Bitstream Vera's successor DejaVu), in order.
fn aliases(family: &str) -> &'static [&'static str] {
    match folded(family).as_str() {
        "bitstreamverasans" => &["DejaVu Sans"],
        "bitstreamveraserif" => &["DejaVu Serif"],
        "bitstreamverasansmono" => &["DejaVu Sans Mono"],
        "arial" | "helvetica" | "arimo" => &["Liberation Sans"],
        "timesnewroman" | "times" | "tinos" => &["Liberation Serif"],
        "couriernew" | "courier" | "cousine" => &["Liberation Mono"],
        _ => &[],
    }
}

/// The face of `family` among `entries` with `style`, else its regular face, else its first.
fn choose<'e>(
    entries: impl Iterator<Item = &'e Entry>,
    family: &str,
    style: Option<&str>,
) -> Option<&'e Entry> {
    let family = folded(family);
    let of_family: Vec<&Entry> = entries.filter(|e| folded(&e.family) == family).collect();
    match style {
        Some(style) => {
            let style = folded(style);
            of_family
                .iter()
                .find(|e| folded(&e.style) == style)
                .or_else(|| of_family.iter().find(|e| is_regular(&e.style)))
        }
        None => of_family.iter().find(|e| is_regular(&e.style)),
    }
    .or(of_family.first())
    .copied()
}

/// The bundled default face.
pub fn bundled() -> FoundFont {
    FoundFont {
        data: bundled_data(),
        index: 0,
        family: DEFAULT_FAMILY.into(),
        style: "Regular".into(),
    }
}

fn bundled_data() -> Arc<Vec<u8>> {
    static DATA: OnceLock<Arc<Vec<u8>>> = OnceLock::new();
    DATA.get_or_init(|| Arc::new(BUNDLED_SANS.to_vec())).clone()
}

fn load(entry: &Entry) -> Option<FoundFont> {
    let data = match &entry.path {
        Some(path) => Arc::new(read_font(path).ok()?),
        None => bundled_data(),
    };
    Some(FoundFont {
        data,
        index: entry.index,
        family: entry.family.clone(),
        style: entry.style.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_as_fontconfig_patterns() {
        assert_eq!(
            parse_name("Liberation Sans:style=Bold Italic"),
            FontName {
                families: vec!["Liberation Sans".into()],
                style: Some("Bold Italic".into())
            }
        );
        assert_eq!(
            parse_name(" A , B "),
            FontName {
                families: vec!["A".into(), "B".into()],
                style: None
            }
        );
        assert_eq!(parse_name("").families, Vec::<String>::new());
    }

    #[test]
    fn the_default_font_is_always_found() {
        let found = find(&parse_name("")).expect("the bundled font");
        assert_eq!(folded(&found.family), "liberationsans");
        assert!(find(&parse_name("No Such Family 123")).is_none());
        // fontconfig's metric aliases: Arial is Liberation Sans (bundled, so always found).
        let arial = find(&parse_name("Arial")).expect("Arial's alias");
        assert_eq!(folded(&arial.family), "liberationsans");
        let face = ttf_parser::Face::parse(BUNDLED_SANS, 0).unwrap();
        assert_eq!(face_names(&face).0, DEFAULT_FAMILY);
    }
}
