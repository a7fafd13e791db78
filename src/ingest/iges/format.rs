//! The IGES 5.3 fixed-format file layer.
//!
//! Records, sections, the Global section, Directory Entries and Parameter Data.
//!
//! An IGES file is a sequence of 80-column records. Column 73 holds the section letter
//! (`S` start, `G` global, `D` directory entry, `P` parameter data, `T` terminate), columns
//! 74–80 the record's sequence number within its section. Each entity has a pair of `D`
//! records of ten 8-column fields (entity type, parameter-data pointer, transformation matrix
//! pointer, status, form, number of `P` records, …) and one or more `P` records whose columns
//! 1–64 hold its free-format parameters and columns 65–72 the back-pointer to its `D` record.
//! Parameters are separated by the Global section's parameter delimiter (default `,`) and
//! end at its record delimiter (default `;`); strings are Hollerith constants `nH…` (n
//! characters after the `H`, which may contain the delimiters); reals may use `D` exponents.
//!
//! Real-world variations handled: CR/LF line ends, trailing blanks stripped from records (so
//! records shorter than 80 columns), 80-byte records with no line breaks at all, blank lines,
//! non-default delimiters, reals written without digits before or after the point (`.5`,
//! `1.`), integers written as reals (`3.`). Not handled (an error says so): the compressed
//! ASCII form (`C` in column 73 of the first record) and binary IGES.
//!
//! Every error is a sentence naming the record (`line 17`), the section, or the Directory
//! Entry (`DE 17`) at fault; the caller adds the file name.

/// Directory Entry of one entity (the two `D` records), with its raw parameters.
#[derive(Clone, Debug)]
pub struct DirEntry {
    /// Sequence number of the first `D` record (odd: 1, 3, 5, …): how other entities point
    /// at this one.
    pub de: usize,
    pub entity_type: i64,
    /// Pointer to the entity's transformation matrix (entity 124), 0 if none.
    pub transform: usize,
    pub form: i64,
    /// Status digits: blank, subordinate, use flag, hierarchy (two digits each).
    pub status: [u8; 4],
    /// The entity's parameters, the entity type number (parameter 0) removed.
    pub params: Vec<Token>,
}

impl DirEntry {
    /// True when no other entity depends on this one (subordinate switch 00).
    pub fn is_independent(&self) -> bool {
        self.status[1] == 0
    }
}

/// One free-format parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Token {
    /// Nothing between two delimiters: the parameter's default value.
    Default,
    /// A Hollerith string.
    Str(String),
    /// A number, as written (integer or real, `D` exponent allowed).
    Num(String),
}

impl Token {
    /// The value as a real number.
    pub fn real(&self) -> Option<f64> {
        match self {
            Token::Num(s) => parse_real(s),
            _ => None,
        }
    }

    /// The value as an integer (a real with no fractional part is accepted).
    pub fn int(&self) -> Option<i64> {
        match self {
            Token::Num(s) => s.parse::<i64>().ok().or_else(|| {
                parse_real(s)
                    .filter(|x| x.fract() == 0.0 && x.abs() < 9e15)
                    .map(|x| x as i64)
            }),
            _ => None,
        }
    }
}

/// Parses an IGES real: Fortran style, `D` or `E` exponent, digits optional on either side
/// of the point.
pub fn parse_real(s: &str) -> Option<f64> {
    let t: String = s
        .trim()
        .chars()
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    let x: f64 = t.parse().ok()?;
    x.is_finite().then_some(x)
}

/// What the Global section says that matters here.
#[derive(Clone, Debug, PartialEq)]
pub struct Global {
    pub param_delim: char,
    pub record_delim: char,
    /// Field 13: model space units per real-world unit (usually 1).
    pub model_scale: f64,
    /// Field 14: 1 inch, 2 mm, 3 named in field 15, 4 foot, 5 mile, 6 metre, 7 km, 8 mil,
    /// 9 micron, 10 cm, 11 microinch.
    pub unit_flag: i64,
    /// Field 15: the unit's name (`MM`, `IN`, …).
    pub unit_name: String,
    /// Field 19: minimum user-intended resolution, in file units (0 when not given).
    pub resolution: f64,
    /// Field 3: the product identification from the sender (for messages).
    pub sender: String,
}

impl Global {
    /// Millimetres per model-space unit, and the unit's short name (as the report shows it).
    pub fn unit(&self) -> Result<(f64, String), String> {
        let named = |name: &str| -> Option<(f64, &'static str)> {
            Some(match name.trim().to_ascii_uppercase().as_str() {
                "IN" | "INCH" => (25.4, "inch"),
                "MM" => (1.0, "mm"),
                "FT" => (304.8, "ft"),
                "MI" => (1_609_344.0, "mi"),
                "M" => (1000.0, "m"),
                "KM" => (1_000_000.0, "km"),
                "MIL" => (0.0254, "mil"),
                "UM" | "MICRON" => (0.001, "um"),
                "CM" => (10.0, "cm"),
                "UIN" => (0.0000254, "uin"),
                _ => return None,
            })
        };
        let (mm, name) = match self.unit_flag {
            1 => (25.4, "inch"),
            2 => (1.0, "mm"),
            3 => named(&self.unit_name).ok_or_else(|| {
                format!(
                    "Global section: unit flag 3 names unit {:?}, which is not known",
                    self.unit_name
                )
            })?,
            4 => (304.8, "ft"),
            5 => (1_609_344.0, "mi"),
            6 => (1000.0, "m"),
            7 => (1_000_000.0, "km"),
            8 => (0.0254, "mil"),
            9 => (0.001, "um"),
            10 => (10.0, "cm"),
            11 => (0.0000254, "uin"),
            f => return Err(format!("Global section: unit flag {f} is not an IGES unit")),
        };
        if !(self.model_scale.is_finite() && self.model_scale > 0.0) {
            return Err(format!(
                "Global section: model space scale {} is not a positive number",
                self.model_scale
            ));
        }
        // Model space = scale × real world: one model unit is 1/scale real units.
        Ok((mm / self.model_scale, name.to_string()))
    }
}

/// A parsed IGES file: the Global section and every Directory Entry, in file order.
#[derive(Clone, Debug)]
pub struct IgesFile {
    pub global: Global,
    pub entries: Vec<DirEntry>,
}

impl IgesFile {
    /// The entity whose Directory Entry starts at sequence number `de`.
    pub fn get(&self, de: usize) -> Option<&DirEntry> {
        if de == 0 || de.is_multiple_of(2) {
            return None;
        }
        self.entries.get((de - 1) / 2)
    }
}

/// The records of each section, with the file line each came from.
#[derive(Default)]
struct Sections<'a> {
    s: Vec<(usize, &'a str)>,
    g: Vec<(usize, &'a str)>,
    d: Vec<(usize, &'a str)>,
    p: Vec<(usize, &'a str)>,
    t: Vec<(usize, &'a str)>,
}

/// Columns `a..b` (0-based, end exclusive) of a record, blank-padded.
fn cols(rec: &str, a: usize, b: usize) -> &str {
    let n = rec.len();
    if a >= n {
        ""
    } else {
        &rec[a..b.min(n)]
    }
}

/// Splits the text into records and sorts them into sections.
fn sections(text: &str) -> Result<Sections<'_>, String> {
    let text = text.trim_start_matches('\u{feff}');
    // Some writers emit fixed 80-byte records with no line breaks at all.
    let records: Vec<&str> = if !text.contains('\n') && !text.contains('\r') && text.len() > 80 {
        if !text.len().is_multiple_of(80) {
            return Err(format!(
                "one line of {} characters, not a multiple of 80 (not fixed-format IGES)",
                text.len()
            ));
        }
        (0..text.len() / 80)
            .map(|k| &text[80 * k..80 * (k + 1)])
            .collect()
    } else {
        text.split('\n')
            .map(|l| l.strip_suffix('\r').unwrap_or(l))
            .collect()
    };
    let mut out = Sections::default();
    let mut order = 0; // S G D P T must come in this order
    for (k, rec) in records.iter().enumerate() {
        let line = k + 1;
        if rec.trim().is_empty() {
            continue;
        }
        // Blanks after column 80 (an editor's or a writer's padding) are not data.
        let rec = if rec.len() > 80 && rec.is_char_boundary(80) && rec[80..].trim().is_empty() {
            &rec[..80]
        } else {
            rec
        };
        if !rec.is_ascii() {
            return Err(format!("line {line}: non-ASCII characters"));
        }
        if rec.len() < 73 {
            return Err(format!(
                "line {line}: {} columns; IGES records have 80 columns with the section letter in column 73 (wrong column layout)",
                rec.len()
            ));
        }
        if rec.len() > 80 {
            return Err(format!(
                "line {line}: {} columns, more than 80 (wrong column layout)",
                rec.len()
            ));
        }
        let letter = rec.as_bytes()[72] as char;
        let rank = match letter {
            'S' => 0,
            'G' => 1,
            'D' => 2,
            'P' => 3,
            'T' => 4,
            'C' if line == 1 => {
                return Err("compressed ASCII IGES (C in column 73) is not supported".into())
            }
            'B' if line == 1 => return Err("binary IGES is not supported".into()),
            c => {
                return Err(format!(
                    "line {line}: column 73 holds {c:?}, not a section letter S, G, D, P or T (wrong column layout)"
                ))
            }
        };
        if rank < order {
            return Err(format!(
                "line {line}: {letter} record after the {} section (sections out of order)",
                [
                    "Start",
                    "Global",
                    "Directory Entry",
                    "Parameter Data",
                    "Terminate"
                ][order]
            ));
        }
        order = rank;
        let seq = cols(rec, 73, 80).trim();
        let list = match letter {
            'S' => &mut out.s,
            'G' => &mut out.g,
            'D' => &mut out.d,
            'P' => &mut out.p,
            _ => &mut out.t,
        };
        // The D and P sequence numbers are what pointers refer to: they must count 1, 2, ….
        if letter == 'D' || letter == 'P' {
            let want = list.len() + 1;
            if seq.parse::<usize>().ok() != Some(want) {
                return Err(format!(
                    "line {line}: {letter} record numbered {seq:?}, expected {want} (records missing, reordered or in the wrong columns)"
                ));
            }
        }
        list.push((line, rec));
    }
    Ok(out)
}

/// Splits free-format parameter text into tokens, up to the record delimiter. Hollerith
/// strings may contain either delimiter. Returns the tokens and whether the record delimiter
/// was met.
pub fn tokenize(text: &str, pd: char, rd: char) -> Result<(Vec<Token>, bool), String> {
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    let mut out = Vec::new();
    let n = chars.len();
    loop {
        while i < n && chars[i] == ' ' {
            i += 1;
        }
        if i >= n {
            return Ok((out, false));
        }
        // Hollerith: digits, then H, then that many characters.
        let mut j = i;
        while j < n && chars[j].is_ascii_digit() {
            j += 1;
        }
        let token = if j > i && j < n && (chars[j] == 'H' || chars[j] == 'h') {
            let len: usize = chars[i..j]
                .iter()
                .collect::<String>()
                .parse()
                .map_err(|_| "Hollerith length too large".to_string())?;
            let start = j + 1;
            if start + len > n {
                return Err(format!(
                    "Hollerith string {}H… runs past the end of the parameters",
                    len
                ));
            }
            let s: String = chars[start..start + len].iter().collect();
            i = start + len;
            while i < n && chars[i] == ' ' {
                i += 1;
            }
            Token::Str(s)
        } else {
            let start = i;
            while i < n && chars[i] != pd && chars[i] != rd {
                i += 1;
            }
            let raw: String = chars[start..i]
                .iter()
                .collect::<String>()
                .trim()
                .to_string();
            if raw.is_empty() {
                Token::Default
            } else {
                Token::Num(raw)
            }
        };
        out.push(token);
        if i >= n {
            return Ok((out, false));
        }
        let c = chars[i];
        i += 1;
        if c == rd {
            return Ok((out, true));
        }
        if c != pd {
            return Err(format!(
                "unexpected {c:?} after a parameter (expected {pd:?} or {rd:?})"
            ));
        }
    }
}

/// Parses the Global section text (columns 1–72 of the `G` records joined).
fn parse_global(text: &str) -> Result<Global, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    let skip_blanks = |i: &mut usize| {
        while *i < chars.len() && chars[*i] == ' ' {
            *i += 1;
        }
    };
    // `1Hc` at i: the delimiter c.
    let hollerith_char = |i: usize| -> Option<char> {
        (i + 2 < chars.len() && chars[i] == '1' && matches!(chars[i + 1], 'H' | 'h'))
            .then(|| chars[i + 2])
    };
    // Field 1, the parameter delimiter: `1Hc`, or empty for the default comma.
    skip_blanks(&mut i);
    let pd = if chars.get(i) == Some(&',') {
        ','
    } else if let Some(c) = hollerith_char(i) {
        i += 3;
        skip_blanks(&mut i);
        c
    } else {
        return Err("Global section: field 1 (parameter delimiter) must be 1Hc or empty".into());
    };
    if chars.get(i) != Some(&pd) {
        return Err(format!(
            "Global section: the parameter delimiter {pd:?} does not follow field 1"
        ));
    }
    i += 1;
    // Field 2, the record delimiter: `1Hc`, or empty for the default semicolon.
    skip_blanks(&mut i);
    let rd = if chars.get(i) == Some(&pd) {
        ';'
    } else if let Some(c) = hollerith_char(i) {
        i += 3;
        skip_blanks(&mut i);
        c
    } else {
        return Err("Global section: field 2 (record delimiter) must be 1Hc or empty".into());
    };
    match chars.get(i) {
        Some(&c) if c == pd => i += 1,
        Some(&c) if c == rd => i = chars.len(),
        _ => {
            return Err(format!(
                "Global section: the parameter delimiter {pd:?} does not follow field 2"
            ))
        }
    }
    let rest: String = chars[i.min(chars.len())..].iter().collect();
    let (tokens, _) = tokenize(&rest, pd, rd).map_err(|e| format!("Global section: {e}"))?;
    // tokens[0] is field 3.
    let field = |k: usize| tokens.get(k - 3).cloned().unwrap_or(Token::Default);
    let real_or = |k: usize, default: f64| -> Result<f64, String> {
        match field(k) {
            Token::Default => Ok(default),
            t => t
                .real()
                .ok_or_else(|| format!("Global section: field {k} is {t:?}, not a number")),
        }
    };
    let int_or = |k: usize, default: i64| -> Result<i64, String> {
        match field(k) {
            Token::Default => Ok(default),
            t => t
                .int()
                .ok_or_else(|| format!("Global section: field {k} is {t:?}, not an integer")),
        }
    };
    let string = |k: usize| match field(k) {
        Token::Str(s) => s,
        _ => String::new(),
    };
    Ok(Global {
        param_delim: pd,
        record_delim: rd,
        model_scale: real_or(13, 1.0)?,
        unit_flag: int_or(14, 1)?,
        unit_name: string(15),
        resolution: real_or(19, 0.0)?,
        sender: string(3),
    })
}

/// An 8-column integer field of a `D` record; blank is 0.
fn de_field(rec: &str, k: usize, de: usize, what: &str) -> Result<i64, String> {
    let s = cols(rec, 8 * k, 8 * k + 8).trim();
    if s.is_empty() {
        return Ok(0);
    }
    s.parse::<i64>().map_err(|_| {
        format!(
            "DE {de}: columns {}–{} ({what}) hold {s:?}, not an integer (wrong column layout)",
            8 * k + 1,
            8 * k + 8
        )
    })
}

/// Parses a whole IGES file.
pub fn parse(text: &str) -> Result<IgesFile, String> {
    let sec = sections(text)?;
    if sec.s.is_empty() && sec.g.is_empty() && sec.d.is_empty() {
        return Err("no Start, Global or Directory Entry records (not an IGES file)".into());
    }
    check_terminate(&sec)?;
    if sec.g.is_empty() {
        return Err("no Global section".into());
    }
    let gtext: String = sec.g.iter().map(|(_, r)| cols(r, 0, 72)).collect();
    let global = parse_global(&gtext)?;
    if sec.d.len() % 2 != 0 {
        return Err(format!(
            "{} Directory Entry records, an odd number (each entity has two)",
            sec.d.len()
        ));
    }
    let mut entries = Vec::with_capacity(sec.d.len() / 2);
    for pair in sec.d.chunks(2) {
        let de = entries.len() * 2 + 1;
        entries.push(dir_entry(&sec, &global, (pair[0].1, pair[1].1), de)?);
    }
    Ok(IgesFile { global, entries })
}

/// Checks the Terminate record's counts of S, G, D and P records against the file.
fn check_terminate(sec: &Sections) -> Result<(), String> {
    let Some(&(tline, trec)) = sec.t.first() else {
        return Err("no Terminate record (file truncated?)".into());
    };
    // Terminate: S, G, D, P counts in fields of 8 columns (letter + 7 digits).
    for (k, (letter, have)) in [
        ('S', sec.s.len()),
        ('G', sec.g.len()),
        ('D', sec.d.len()),
        ('P', sec.p.len()),
    ]
    .into_iter()
    .enumerate()
    {
        let f = cols(trec, 8 * k, 8 * k + 8);
        let ok_letter = f.starts_with(letter);
        let count = f.get(1..).and_then(|s| s.trim().parse::<usize>().ok());
        match (ok_letter, count) {
            (true, Some(c)) if c == have => {}
            (true, Some(c)) => {
                return Err(format!(
                    "Terminate record (line {tline}) counts {c} {letter} records, the file has {have} (file truncated or damaged)"
                ))
            }
            _ => {
                return Err(format!(
                    "Terminate record (line {tline}): columns {}–{} should be {letter} and a count, found {f:?} (wrong column layout)",
                    8 * k + 1,
                    8 * k + 8
                ))
            }
        }
    }
    Ok(())
}

/// The entity of the two `D` records `(r1, r2)` numbered `de`, with its parameters.
fn dir_entry(
    sec: &Sections,
    global: &Global,
    (r1, r2): (&str, &str),
    de: usize,
) -> Result<DirEntry, String> {
    let entity_type = de_field(r1, 0, de, "entity type")?;
    let pd = de_field(r1, 1, de, "parameter data pointer")?;
    let transform = de_field(r1, 6, de, "transformation matrix pointer")?;
    let status_s = cols(r1, 64, 72);
    let type2 = de_field(r2, 0, de, "entity type")?;
    let count = de_field(r2, 3, de, "parameter line count")?;
    let form = de_field(r2, 4, de, "form number")?;
    if type2 != entity_type {
        return Err(format!(
            "DE {de}: entity type {entity_type} on the first record, {type2} on the second (wrong column layout)"
        ));
    }
    let mut status = [0u8; 4];
    let digits: String = format!("{:0>8}", status_s.trim());
    for (k, s) in status.iter_mut().enumerate() {
        *s = digits
            .get(2 * k..2 * k + 2)
            .and_then(|d| d.parse().ok())
            .ok_or_else(|| {
                format!("DE {de}: status field {status_s:?} is not 8 digits (wrong column layout)")
            })?;
    }
    if transform < 0 || transform as usize > sec.d.len() {
        return Err(format!(
            "DE {de}: transformation matrix pointer {transform} points outside the Directory Entry section (1–{})",
            sec.d.len()
        ));
    }
    let params = if entity_type != 0 {
        entity_params(sec, global, de, entity_type, pd, count)?
    } else {
        Vec::new()
    };
    Ok(DirEntry {
        de,
        entity_type,
        transform: transform as usize,
        form,
        status,
        params,
    })
}

/// The parameters of entity `de` (of type `entity_type`): its `count` `P` records from the
/// pointer `pd`, which must point back to it, tokenized, the leading entity type checked and
/// removed.
fn entity_params(
    sec: &Sections,
    global: &Global,
    de: usize,
    entity_type: i64,
    pd: i64,
    count: i64,
) -> Result<Vec<Token>, String> {
    let np = sec.p.len();
    if pd < 1 || pd as usize > np {
        return Err(format!(
            "DE {de} (entity {entity_type}): parameter data pointer {pd} outside the Parameter Data section (1–{np}; file truncated?)"
        ));
    }
    let count = count.max(1) as usize;
    let first = pd as usize - 1;
    if first + count > np {
        return Err(format!(
            "DE {de} (entity {entity_type}): its {count} parameter records run past the end of the Parameter Data section ({np} records; file truncated?)"
        ));
    }
    let mut text = String::new();
    for &(line, rec) in &sec.p[first..first + count] {
        let back = cols(rec, 64, 72).trim();
        if back.parse::<usize>().ok() != Some(de) {
            return Err(format!(
                "line {line}: parameter record of DE {de} (entity {entity_type}) points back to DE {back:?} (wrong column layout or bad pointer)"
            ));
        }
        text.push_str(&format!("{:<64}", cols(rec, 0, 64)));
    }
    let (tokens, ended) = tokenize(&text, global.param_delim, global.record_delim)
        .map_err(|e| format!("DE {de} (entity {entity_type}): {e}"))?;
    if !ended {
        return Err(format!(
            "DE {de} (entity {entity_type}): parameters do not end with the record delimiter {:?} (truncated?)",
            global.record_delim
        ));
    }
    let mut tokens = tokens.into_iter();
    let head = tokens.next();
    if head.as_ref().and_then(|t| t.int()) != Some(entity_type) {
        let what = match head {
            Some(Token::Num(x)) => x,
            Some(Token::Str(x)) => format!("the string {x:?}"),
            _ => "nothing".into(),
        };
        return Err(format!(
            "DE {de}: parameter data starts with {what}, not the entity type {entity_type}"
        ));
    }
    Ok(tokens.collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 80-column record.
    fn rec(data: &str, letter: char, seq: usize) -> String {
        format!("{data:<72}{letter}{seq:>7}")
    }

    fn pd(data: &str, de: usize, seq: usize) -> String {
        format!("{data:<64}{de:>8}P{seq:>7}")
    }

    fn de(
        ty: i64,
        pd: usize,
        tr: usize,
        status: &str,
        count: usize,
        form: i64,
        seq: usize,
    ) -> String {
        let l1 = format!(
            "{ty:>8}{pd:>8}{:>8}{:>8}{:>8}{:>8}{tr:>8}{:>8}{status:>8}D{seq:>7}",
            0, 0, 0, 0, 0
        );
        let l2 = format!(
            "{ty:>8}{:>8}{:>8}{count:>8}{form:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            0,
            0,
            "",
            "",
            "",
            0,
            seq + 1
        );
        format!("{l1}\n{l2}")
    }

    /// A two-entity file: a line and a point (the line's record split over two P lines).
    fn small(global: &str) -> String {
        let g: Vec<String> = global
            .as_bytes()
            .chunks(72)
            .enumerate()
            .map(|(k, c)| rec(std::str::from_utf8(c).unwrap(), 'G', k + 1))
            .collect();
        let lines = [
            rec("a test", 'S', 1),
            g.join("\n"),
            de(110, 1, 0, "00000000", 2, 0, 1),
            de(116, 3, 0, "00010000", 1, 0, 3),
            pd("110,0.,1.5D0,-2.,", 1, 1),
            pd(".5,1.E+01,3;", 1, 2),
            pd("116,1.,2.,3.,0;", 3, 3),
            format!(
                "{:<72}T{:>7}",
                format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, g.len(), 4, 3),
                1
            ),
        ];
        lines.join("\n") + "\n"
    }

    const GLOBAL: &str = "1H,,1H;,4Htest,8Hfile.igs,3Hsys,3Hpre,32,308,15,308,15,,1.,2,2HMM,1,0.01,15H20261122.054705,1E-07,15.,,,11,0,;";

    #[test]
    fn parses_a_small_file() {
        let f = parse(&small(GLOBAL)).unwrap();
        assert_eq!(f.entries.len(), 2);
        let line = f.get(1).unwrap();
        assert_eq!(line.entity_type, 110);
        let xs: Vec<f64> = line.params.iter().map(|t| t.real().unwrap()).collect();
        assert_eq!(xs, vec![0.0, 1.5, -2.0, 0.5, 10.0, 3.0]);
        assert!(line.is_independent());
        let point = f.get(3).unwrap();
        assert!(!point.is_independent());
        assert_eq!(f.global.unit(), Ok((1.0, "mm".to_string())));
        assert_eq!(f.global.resolution, 1e-7);
        assert_eq!(f.global.sender, "test");
    }

    #[test]
    fn default_and_custom_delimiters() {
        let g = parse_global(",,4Htest,,,,,,,,,,2.,1,2HIN,;").unwrap();
        assert_eq!((g.param_delim, g.record_delim), (',', ';'));
        assert_eq!(g.unit_flag, 1);
        assert_eq!(g.model_scale, 2.0);
        // One model unit is half an inch.
        assert_eq!(g.unit().unwrap().0, 12.7);
        let g = parse_global("1H//1H#/6HA/B#CD//////////1./6#").unwrap();
        assert_eq!((g.param_delim, g.record_delim), ('/', '#'));
        assert_eq!(g.sender, "A/B#CD");
        assert_eq!(g.unit_flag, 6);
        assert_eq!(g.unit().unwrap().0, 1000.0);
    }

    #[test]
    fn hollerith_with_delimiters_inside() {
        let (t, end) = tokenize("4H1,;2, 3H;;;,,7;junk", ',', ';').unwrap();
        assert!(end);
        assert_eq!(
            t,
            vec![
                Token::Str("1,;2".into()),
                Token::Str(";;;".into()),
                Token::Default,
                Token::Num("7".into())
            ]
        );
        assert!(tokenize("9Habc", ',', ';').is_err());
    }

    #[test]
    fn reals() {
        assert_eq!(parse_real("1.D-3"), Some(1e-3));
        assert_eq!(parse_real("-.25"), Some(-0.25));
        assert_eq!(parse_real("7."), Some(7.0));
        assert_eq!(parse_real("1.5E+02"), Some(150.0));
        assert_eq!(parse_real("abc"), None);
        assert_eq!(Token::Num("3.".into()).int(), Some(3));
        assert_eq!(Token::Num("3.5".into()).int(), None);
    }

    #[test]
    fn crlf_unbroken_and_padded_records() {
        let text = small(GLOBAL);
        let crlf = text.replace('\n', "\r\n");
        assert_eq!(parse(&crlf).unwrap().entries.len(), 2);
        let unbroken: String = text.lines().collect();
        assert_eq!(parse(&unbroken).unwrap().entries.len(), 2);
        // Blanks after column 80.
        let padded: String = text.lines().map(|l| format!("{l}   \n")).collect();
        assert_eq!(parse(&padded).unwrap().entries.len(), 2);
    }

    #[test]
    fn errors_name_the_problem() {
        let text = small(GLOBAL);
        // Truncated: the terminate record is gone, and then a P record too.
        let cut: Vec<&str> = text.lines().collect();
        let e = parse(&cut[..cut.len() - 1].join("\n")).unwrap_err();
        assert!(e.contains("no Terminate record"), "{e}");
        let mut lines: Vec<String> = cut.iter().map(|s| s.to_string()).collect();
        lines.remove(lines.len() - 2);
        let e = parse(&lines.join("\n")).unwrap_err();
        assert!(e.contains("counts 3 P records, the file has 2"), "{e}");
        // Columns shifted by one.
        let shifted: String = text.lines().map(|l| format!(" {l}\n")).collect();
        let e = parse(&shifted).unwrap_err();
        assert!(e.contains("wrong column layout"), "{e}");
        // Short records.
        let e = parse("hello\nworld\n").unwrap_err();
        assert!(e.contains("line 1: 5 columns"), "{e}");
        // A DE pointing past the Parameter Data section.
        let bad = text.replacen(
            &de(116, 3, 0, "00010000", 1, 0, 3),
            &de(116, 9, 0, "00010000", 1, 0, 3),
            1,
        );
        let e = parse(&bad).unwrap_err();
        assert!(
            e.contains("DE 3 (entity 116): parameter data pointer 9"),
            "{e}"
        );
        // Parameters without the record delimiter.
        let bad = text.replace("116,1.,2.,3.,0;", "116,1.,2.,3.,0 ");
        let e = parse(&bad).unwrap_err();
        assert!(e.contains("do not end with the record delimiter"), "{e}");
    }
}
