//! The top-level keys of a scene file and the rules for their plain values.

use crate::table::{ChoiceKey, Drive, Lateral, Law, Motion, Normal, Support};

/// A value as an error message shows it: at most 200 characters, then how long it was.
pub fn shown(s: &str) -> String {
    const MAX: usize = 200;
    match s.char_indices().nth(MAX) {
        None => s.to_string(),
        Some((cut, _)) => format!("{}… ({} bytes)", &s[..cut], s.len()),
    }
}

/// Longest model identifier: it names the FMU file, its library and the C symbols' prefix.
pub const MAX_IDENTIFIER: usize = 64;

/// What a top-level key takes, for the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyValues {
    /// Described in words.
    Text(&'static str),
    /// One of these words.
    OneOf(&'static [&'static str]),
    /// A non-empty array of these words.
    ArrayOf(&'static [&'static str]),
}

/// A top-level key of a scene file: its name, what it takes, whether it is required (or its
/// default) and what it means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    pub name: &'static str,
    pub values: KeyValues,
    pub requirement: &'static str,
    pub meaning: &'static str,
}

impl Key {
    const fn choice(k: ChoiceKey) -> Key {
        Key {
            name: k.name,
            values: KeyValues::OneOf(k.words),
            requirement: k.requirement,
            meaning: k.meaning,
        }
    }
}

/// The top-level keys of a scene file, in the order the documentation lists them; the choice
/// keys are the rows of `table/config.rs`.
pub const KEYS: [Key; 11] = [
    Key {
        name: "model_identifier",
        values: KeyValues::Text("string (C identifier)"),
        requirement: "required",
        meaning: "The FMU's model identifier: its file name `<model_identifier>.fmu` and the name of its shared library. A C identifier (a letter or `_`, then letters, digits or `_`; not a C keyword), different in every scene exported together.",
    },
    Key {
        name: "description",
        values: KeyValues::Text("string"),
        requirement: "default: a summary of law, motion, drive and support motion",
        meaning: "Free text, shown by importers and on the FMU's documentation page.",
    },
    Key::choice(Law::KEY),
    Key::choice(Motion::KEY),
    Key::choice(Drive::KEY),
    Key::choice(Lateral::KEY),
    Key {
        values: KeyValues::ArrayOf(Support::KEY.words),
        ..Key::choice(Support::KEY)
    },
    Key::choice(Normal::KEY),
    Key {
        name: "outputs",
        values: KeyValues::Text("array of output names"),
        requirement: "default: every output the scene can have",
        meaning: "The outputs the FMU exposes, a non-empty array of names (see the tables below for which a scene can have).",
    },
    Key {
        name: "start",
        values: KeyValues::Text("table: name = number"),
        requirement: "default: none",
        meaning: "A table of start values that override the defaults: any parameter or input of the scene (see the tables below), in SI units. In a string scene a per-section variable takes one number for every section or a list of one per section (one per link for `k_s`, `c_s`).",
    },
    Key {
        name: "string",
        values: KeyValues::Text("table: sections = N"),
        requirement: "default: none (a single contact)",
        meaning: "A string of contacts: `sections = N` (1 to 100000) bodies in a line, each on its own contact of the scene's law and support, joined by links (`k_s`, `c_s`) and held at the ends (`k_top`, `c_top`, `k_bottom`, `c_bottom`). Only with `motion = \"longitudinal\"` and `drive = \"force\"`; the scene then has no `outputs` key (every output of every section).",
    },
];

/// True when `s` is a valid C identifier that is not a C keyword.
pub fn is_c_identifier(s: &str) -> bool {
    const KEYWORDS: [&str; 44] = [
        "auto",
        "break",
        "case",
        "char",
        "const",
        "continue",
        "default",
        "do",
        "double",
        "else",
        "enum",
        "extern",
        "float",
        "for",
        "goto",
        "if",
        "inline",
        "int",
        "long",
        "register",
        "restrict",
        "return",
        "short",
        "signed",
        "sizeof",
        "static",
        "struct",
        "switch",
        "typedef",
        "union",
        "unsigned",
        "void",
        "volatile",
        "while",
        "_Alignas",
        "_Alignof",
        "_Atomic",
        "_Bool",
        "_Complex",
        "_Generic",
        "_Imaginary",
        "_Noreturn",
        "_Static_assert",
        "_Thread_local",
    ];
    let mut chars = s.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_') && !KEYWORDS.contains(&s)
}
