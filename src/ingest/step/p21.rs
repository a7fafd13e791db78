//! A reader for ISO 10303-21 exchange files (STEP "Part 21" text) that builds ruststep's AST.
//!
//! truck converts entities from ruststep's AST, so that is what this module produces; it
//! replaces ruststep's own nom parser, which spent three quarters of the ingestion time in
//! allocation and backtracking (about 400 ms per MB) and which
//! - rejected strings with an escaped apostrophe (`'it''s'`), which the standard allows;
//! - recursed once per nested list, so a hostile file could overflow the stack;
//! - panicked on an integer too large for `i64`.
//!
//! This reader makes one pass over the bytes, allocates only the AST, nests at most
//! `max_nesting` parentheses deep, and reports errors with line and column.
//!
//! Points and directions, most of a B-rep file (four in five instances of a part made of
//! B-spline patches), are kept compact when written in their usual form
//! `CARTESIAN_POINT('label',(x,y,z))`: a [`CompactPoint`] instead of a record with three
//! heap-allocated lists and names. [`Item::to_instance`] gives the record ruststep would
//! have read.
//! Semantics otherwise follow ruststep (the tests compare both on every sample): keywords as
//! written (a user-defined `!NAME` loses its `!`), `.T.` is an enumeration, strings are kept
//! undecoded but for `''` → `'`, and `ANCHOR`, `REFERENCE` and `SIGNATURE` sections are read
//! over and dropped (truck reads none of them).

use truck_stepio::r#in::ruststep::ast::{
    DataSection, EntityInstance, Name, Parameter, Record, SubSuperRecord,
};

/// A parsed exchange structure: the header records and the data sections, in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct Parsed {
    pub header: Vec<Record>,
    pub data: Vec<Section>,
}

/// A data section: its parameters (`DATA(…);`) and its instances in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub meta: Vec<Parameter>,
    pub entities: Vec<Item>,
}

/// One instance of a data section.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// Any instance, as ruststep's AST.
    Instance(EntityInstance),
    /// A point or direction in its usual form, kept compact.
    Point(CompactPoint),
}

/// Which entity a [`CompactPoint`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointKind {
    CartesianPoint,
    Direction,
}

impl PointKind {
    /// The entity name.
    pub fn name(self) -> &'static str {
        match self {
            PointKind::CartesianPoint => "CARTESIAN_POINT",
            PointKind::Direction => "DIRECTION",
        }
    }
}

/// `#id = CARTESIAN_POINT('label', (x, y, z));` (or `DIRECTION`) with one to three reals.
#[derive(Debug, Clone, PartialEq)]
pub struct CompactPoint {
    pub id: u64,
    pub kind: PointKind,
    pub label: String,
    coords: [f64; 3],
    len: u8,
}

impl CompactPoint {
    /// A point or direction with one to three coordinates.
    pub fn new(id: u64, kind: PointKind, label: String, coords: &[f64]) -> Self {
        assert!((1..=3).contains(&coords.len()), "1 to 3 coordinates");
        let mut c = [0.0; 3];
        c[..coords.len()].copy_from_slice(coords);
        CompactPoint {
            id,
            kind,
            label,
            coords: c,
            len: coords.len() as u8,
        }
    }

    /// The coordinates (direction ratios), as written.
    pub fn coords(&self) -> &[f64] {
        &self.coords[..usize::from(self.len)]
    }

    /// Replaces the coordinates (as many as there were).
    pub fn set_coords(&mut self, coords: &[f64]) {
        let n = usize::from(self.len).min(coords.len());
        self.coords[..n].copy_from_slice(&coords[..n]);
    }

    /// The record ruststep reads for it.
    pub fn to_record(&self) -> Record {
        Record {
            name: self.kind.name().into(),
            parameter: Parameter::List(vec![
                Parameter::String(self.label.clone()),
                Parameter::List(self.coords().iter().map(|&x| Parameter::Real(x)).collect()),
            ]),
        }
    }
}

impl Item {
    /// The instance's id.
    pub fn id(&self) -> u64 {
        match self {
            Item::Instance(EntityInstance::Simple { id, .. })
            | Item::Instance(EntityInstance::Complex { id, .. }) => *id,
            Item::Point(p) => p.id,
        }
    }

    /// The instance as ruststep's AST.
    pub fn to_instance(&self) -> EntityInstance {
        match self {
            Item::Instance(inst) => inst.clone(),
            Item::Point(p) => EntityInstance::Simple {
                id: p.id,
                record: p.to_record(),
            },
        }
    }
}

impl Parsed {
    /// The data sections as ruststep's AST (compact points expanded).
    pub fn data_sections(&self) -> Vec<DataSection> {
        self.data
            .iter()
            .map(|s| DataSection {
                meta: s.meta.clone(),
                entities: s.entities.iter().map(Item::to_instance).collect(),
            })
            .collect()
    }
}

/// Where and why the text is not a valid exchange structure.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntaxError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    pub message: String,
}

impl std::fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

/// Parses a whole exchange file. `max_nesting` bounds parenthesis depth (records count).
pub fn parse(text: &str, max_nesting: usize) -> Result<Parsed, SyntaxError> {
    let mut p = Parser {
        text,
        b: text.as_bytes(),
        i: 0,
        depth: 0,
        max_nesting,
    };
    p.exchange()
}

/// The most instances a data section's list is allocated for before it is read (about 5 MB).
const MAX_RESERVED_INSTANCES: usize = 1 << 16;

/// A record's parameter list is allocated for this many parameters: most B-rep records have
/// 2 to 6, and a list grown from empty would be allocated for 4 and again for 8.
const RECORD_CAPACITY: usize = 6;

struct Parser<'a> {
    text: &'a str,
    b: &'a [u8],
    i: usize,
    depth: usize,
    max_nesting: usize,
}

type R<T> = Result<T, SyntaxError>;

fn is_upper(c: u8) -> bool {
    c.is_ascii_uppercase() || c == b'_'
}

fn is_keyword_char(c: u8) -> bool {
    c.is_ascii_uppercase() || c.is_ascii_digit() || c == b'_'
}

impl<'a> Parser<'a> {
    fn error_at(&self, at: usize, message: impl Into<String>) -> SyntaxError {
        let at = at.min(self.b.len());
        let before = &self.b[..at];
        let line = 1 + before.iter().filter(|&&c| c == b'\n').count();
        let line_start = before
            .iter()
            .rposition(|&c| c == b'\n')
            .map_or(0, |k| k + 1);
        // Column in characters; `at` is always on a char boundary (we stop on ASCII bytes).
        let column = 1 + self
            .text
            .get(line_start..at)
            .map_or(at - line_start, |s| s.chars().count());
        SyntaxError {
            line,
            column,
            message: message.into(),
        }
    }

    fn error(&self, message: impl Into<String>) -> SyntaxError {
        self.error_at(self.i, message)
    }

    /// What is at the cursor, for messages.
    fn found(&self) -> String {
        match self.text.get(self.i..).and_then(|s| s.chars().next()) {
            None => "the end of the file".into(),
            Some(c) if c.is_control() => format!("{:?}", c),
            Some(_) => {
                let rest = &self.text[self.i..];
                let end = rest
                    .char_indices()
                    .take(12)
                    .find(|&(_, c)| c.is_whitespace())
                    .map_or_else(
                        || rest.char_indices().nth(12).map_or(rest.len(), |(k, _)| k),
                        |(k, _)| k,
                    );
                format!("'{}'", &rest[..end.max(1)])
            }
        }
    }

    fn expected(&self, what: &str) -> SyntaxError {
        self.error(format!("expected {what}, found {}", self.found()))
    }

    /// Skips white space and comments.
    #[inline]
    fn ws(&mut self) -> R<()> {
        // Most calls land on a token: no white space, no comment.
        match self.b.get(self.i) {
            Some(&c) if c > b' ' && c != b'/' => Ok(()),
            _ => self.ws_slow(),
        }
    }

    fn ws_slow(&mut self) -> R<()> {
        loop {
            while self.i < self.b.len() && self.b[self.i].is_ascii_whitespace() {
                self.i += 1;
            }
            if self.b.get(self.i) == Some(&b'/') && self.b.get(self.i + 1) == Some(&b'*') {
                let start = self.i;
                match self.text[self.i + 2..].find("*/") {
                    Some(k) => self.i += 2 + k + 2,
                    None => return Err(self.error_at(start, "comment is never closed (no */)")),
                }
            } else {
                return Ok(());
            }
        }
    }

    fn peek(&mut self) -> R<Option<u8>> {
        self.ws()?;
        Ok(self.b.get(self.i).copied())
    }

    fn eat(&mut self, c: u8) -> R<bool> {
        if self.peek()? == Some(c) {
            self.i += 1;
            Ok(true)
        } else {
            Ok(false)
        }
    }

    /// Consumes `c`; the context for the message is only built on failure.
    fn expect<S: std::fmt::Display>(&mut self, c: u8, context: impl FnOnce() -> S) -> R<()> {
        if self.eat(c)? {
            Ok(())
        } else {
            Err(self.expected(&format!("'{}' {}", c as char, context())))
        }
    }

    /// A word of letters, digits, `_` and `-` (section keywords such as END-ISO-10303-21).
    fn word(&mut self) -> R<&'a str> {
        self.ws()?;
        let start = self.i;
        while self.i < self.b.len()
            && (self.b[self.i].is_ascii_alphanumeric() || matches!(self.b[self.i], b'_' | b'-'))
        {
            self.i += 1;
        }
        Ok(&self.text[start..self.i])
    }

    /// A standard keyword `[A-Z_][A-Z0-9_]*`, or a user-defined one `!KEYWORD` (returned
    /// without the `!`, as ruststep does).
    fn keyword(&mut self) -> R<String> {
        self.ws()?;
        if self.b.get(self.i) == Some(&b'!') {
            self.i += 1;
        }
        let start = self.i;
        if !self.b.get(self.i).is_some_and(|&c| is_upper(c)) {
            return Err(self.expected("an entity keyword (upper case)"));
        }
        while self.i < self.b.len() && is_keyword_char(self.b[self.i]) {
            self.i += 1;
        }
        Ok(self.text[start..self.i].to_string())
    }

    fn open(&mut self) -> R<()> {
        self.depth += 1;
        if self.depth > self.max_nesting {
            return Err(self.error(format!(
                "lists nested more than {} deep; no STEP schema needs that",
                self.max_nesting
            )));
        }
        Ok(())
    }

    fn exchange(&mut self) -> R<Parsed> {
        if self.text.starts_with('\u{feff}') {
            self.i = '\u{feff}'.len_utf8();
        }
        if self.word()? != "ISO-10303-21" {
            return Err(self.error_at(0, "does not start with ISO-10303-21; (not a STEP file)"));
        }
        self.expect(b';', || "after ISO-10303-21")?;
        let mut ex = Parsed {
            header: vec![],
            data: vec![],
        };
        let mut seen_header = false;
        loop {
            let at = {
                self.ws()?;
                self.i
            };
            let w = self.word()?;
            match w {
                "HEADER" => {
                    if seen_header {
                        return Err(self.error_at(at, "a second HEADER section"));
                    }
                    seen_header = true;
                    self.expect(b';', || "after HEADER")?;
                    while self.peek_word()? != "ENDSEC" {
                        let r = self.record()?;
                        self.expect(b';', || format!("after header entity {}", r.name))?;
                        ex.header.push(r);
                    }
                    self.end_section()?;
                }
                "DATA" => {
                    if !seen_header {
                        return Err(self.error_at(at, "DATA section before the HEADER section"));
                    }
                    let meta = if self.eat(b'(')? {
                        self.open()?;
                        let list = self.list_items(0)?;
                        self.depth -= 1;
                        list
                    } else {
                        vec![]
                    };
                    self.expect(b';', || "after DATA")?;
                    // At most one instance per ';' to come: counting them (memchr, vectorised)
                    // is far cheaper than growing a list of large items by doubling (6 % of
                    // parsing FTC 09). Capped, so that a file of semicolons in a comment
                    // cannot reserve gigabytes; larger sections grow as they are read.
                    let rest = &self.b[self.i..];
                    let bound = memchr::memchr_iter(b';', rest).count();
                    let mut entities =
                        Vec::with_capacity(bound.min(rest.len() / 8).min(MAX_RESERVED_INSTANCES));
                    loop {
                        match self.peek()? {
                            Some(b'#') => entities.push(self.instance()?),
                            _ if self.peek_word()? == "ENDSEC" => break,
                            _ => {
                                return Err(self.expected("an entity instance (#id = …) or ENDSEC"))
                            }
                        }
                    }
                    self.end_section()?;
                    ex.data.push(Section { meta, entities });
                }
                "ANCHOR" | "REFERENCE" | "SIGNATURE" => self.skip_section(w)?,
                "END-ISO-10303-21" => {
                    self.expect(b';', || "after END-ISO-10303-21")?;
                    if !seen_header {
                        return Err(self.error_at(at, "no HEADER section"));
                    }
                    return Ok(ex);
                }
                "" if self.i >= self.b.len() => {
                    return Err(self.error("the file ends before END-ISO-10303-21; (truncated?)"))
                }
                _ => {
                    self.i = at;
                    return Err(self.expected("a section (HEADER, DATA, ENDSEC, END-ISO-10303-21)"));
                }
            }
        }
    }

    /// The next word, without consuming it.
    fn peek_word(&mut self) -> R<&'a str> {
        let save = self.i;
        let w = self.word()?;
        self.i = save;
        Ok(w)
    }

    fn end_section(&mut self) -> R<()> {
        let w = self.word()?;
        if w != "ENDSEC" {
            return Err(self.expected("ENDSEC"));
        }
        self.expect(b';', || "after ENDSEC")
    }

    /// Reads over a section truck has no use for, up to its ENDSEC;, minding strings and
    /// comments.
    fn skip_section(&mut self, name: &str) -> R<()> {
        let start = self.i;
        loop {
            self.ws()?;
            match self.b.get(self.i) {
                None => return Err(self.error_at(start, format!("{name} section never ends"))),
                Some(b'\'') => {
                    self.string()?;
                }
                Some(c) if c.is_ascii_uppercase() => {
                    if self.word()? == "ENDSEC" && self.eat(b';')? {
                        return Ok(());
                    }
                }
                Some(_) => self.i += 1,
            }
        }
    }

    fn instance(&mut self) -> R<Item> {
        let at = self.i;
        self.i += 1; // '#'
        let id = self
            .digits_u64()?
            .ok_or_else(|| self.expected("an entity id after '#'"))?;
        self.expect(b'=', || format!("after #{id}"))?;
        if let Some(point) = self.compact_point(id)? {
            return Ok(Item::Point(point));
        }
        let inst = if self.peek()? == Some(b'(') {
            self.i += 1;
            self.open()?;
            let mut records = Vec::new();
            while !self.eat(b')')? {
                records.push(self.record()?);
            }
            self.depth -= 1;
            if records.is_empty() {
                return Err(self.error_at(at, format!("#{id} is an empty complex instance")));
            }
            EntityInstance::Complex {
                id,
                subsuper: SubSuperRecord(records),
            }
        } else {
            EntityInstance::Simple {
                id,
                record: self.record()?,
            }
        };
        self.expect(b';', || format!("at the end of #{id}"))?;
        Ok(Item::Instance(inst))
    }

    /// After `#id =`: a `CARTESIAN_POINT` or `DIRECTION` of the form `('label', (reals));`
    /// with one to three reals, read to its `;`. Anything else (another entity, `$` for the
    /// label, integers, a comment inside) leaves the cursor where it was and gives `None`,
    /// for the general reader, which also gives the same errors as for any other record.
    fn compact_point(&mut self, id: u64) -> R<Option<CompactPoint>> {
        self.ws()?;
        let start = self.i;
        let kind = if self.b[start..].starts_with(b"CARTESIAN_POINT") {
            PointKind::CartesianPoint
        } else if self.b[start..].starts_with(b"DIRECTION") {
            PointKind::Direction
        } else {
            return Ok(None);
        };
        // The record's list and the coordinate list: two levels.
        if self.depth + 2 > self.max_nesting {
            return Ok(None);
        }
        self.i += kind.name().len();
        let point = self.compact_point_body(id, kind);
        if point.is_none() {
            self.i = start;
        }
        Ok(point)
    }

    /// The rest of [`Self::compact_point`], after the keyword; `None` on any deviation.
    fn compact_point_body(&mut self, id: u64, kind: PointKind) -> Option<CompactPoint> {
        // White space between tokens; a comment or anything unusual goes the general way
        // (which also reports its errors).
        fn skip(p: &mut Parser<'_>) {
            while p.b.get(p.i).is_some_and(|c| c.is_ascii_whitespace()) {
                p.i += 1;
            }
        }
        fn token(p: &mut Parser<'_>, c: u8) -> bool {
            skip(p);
            let ok = p.b.get(p.i) == Some(&c);
            p.i += usize::from(ok);
            ok
        }
        if !token(self, b'(') {
            return None;
        }
        skip(self);
        if self.b.get(self.i) != Some(&b'\'') {
            return None;
        }
        let label = self.string().ok()?;
        if !token(self, b',') || !token(self, b'(') {
            return None;
        }
        let mut coords = [0.0; 3];
        let mut n = 0;
        loop {
            skip(self);
            if n == 3 || !matches!(self.b.get(self.i), Some(b'+' | b'-' | b'.' | b'0'..=b'9')) {
                return None;
            }
            let Ok(Parameter::Real(x)) = self.number() else {
                return None;
            };
            coords[n] = x;
            n += 1;
            skip(self);
            match self.b.get(self.i) {
                Some(b',') => self.i += 1,
                Some(b')') => {
                    self.i += 1;
                    break;
                }
                _ => return None,
            }
        }
        if !token(self, b')') || !token(self, b';') {
            return None;
        }
        Some(CompactPoint::new(id, kind, label, &coords[..n]))
    }

    /// `KEYWORD ( parameters )`; the parameters become one list parameter, as in ruststep.
    fn record(&mut self) -> R<Record> {
        let name = self.keyword()?;
        self.expect(b'(', || format!("after {name}"))?;
        self.open()?;
        let params = self.list_items(RECORD_CAPACITY)?;
        self.depth -= 1;
        Ok(Record {
            name,
            parameter: Parameter::List(params),
        })
    }

    /// Comma-separated parameters up to and including the closing ')'. The '(' is read.
    /// `capacity` is what the list is allocated with when not empty.
    fn list_items(&mut self, capacity: usize) -> R<Vec<Parameter>> {
        if self.eat(b')')? {
            return Ok(Vec::new());
        }
        let mut items = Vec::with_capacity(capacity);
        loop {
            items.push(self.parameter()?);
            match self.peek()? {
                Some(b',') => self.i += 1,
                Some(b')') => {
                    self.i += 1;
                    return Ok(items);
                }
                _ => return Err(self.expected("',' or ')' in a parameter list")),
            }
        }
    }

    fn parameter(&mut self) -> R<Parameter> {
        let Some(c) = self.peek()? else {
            return Err(self.expected("a parameter"));
        };
        Ok(match c {
            b'$' => {
                self.i += 1;
                Parameter::NotProvided
            }
            b'*' => {
                self.i += 1;
                Parameter::Omitted
            }
            b'\'' => Parameter::String(self.string()?),
            b'#' | b'@' => {
                self.i += 1;
                Parameter::Ref(self.name(c)?)
            }
            b'(' => {
                self.i += 1;
                self.open()?;
                let items = self.list_items(0)?;
                self.depth -= 1;
                Parameter::List(items)
            }
            b'.' if self.b.get(self.i + 1).is_some_and(|&d| is_upper(d)) => {
                self.i += 1;
                let start = self.i;
                while self.i < self.b.len() && is_keyword_char(self.b[self.i]) {
                    self.i += 1;
                }
                let e = self.text[start..self.i].to_string();
                if self.b.get(self.i) != Some(&b'.') {
                    return Err(self.expected(&format!("'.' closing the enumeration .{e}")));
                }
                self.i += 1;
                Parameter::Enumeration(e)
            }
            b'+' | b'-' | b'.' | b'0'..=b'9' => self.number()?,
            b'!' | b'A'..=b'Z' | b'_' => {
                let keyword = self.keyword()?;
                self.expect(b'(', || format!("after the type {keyword}"))?;
                self.open()?;
                let inner = self.parameter()?;
                self.expect(b')', || format!("closing {keyword}(…)"))?;
                self.depth -= 1;
                Parameter::Typed {
                    keyword,
                    parameter: Box::new(inner),
                }
            }
            b'"' => return Err(self.error("binary parameters (\"…\") are not supported")),
            _ => return Err(self.expected("a parameter")),
        })
    }

    /// After `#` or `@`: an instance number or a constant name.
    fn name(&mut self, sigil: u8) -> R<Name> {
        if let Some(n) = self.digits_u64()? {
            return Ok(if sigil == b'#' {
                Name::Entity(n)
            } else {
                Name::Value(n)
            });
        }
        if self.b.get(self.i).is_some_and(|&c| is_upper(c)) {
            let k = self.keyword()?;
            return Ok(if sigil == b'#' {
                Name::ConstantEntity(k)
            } else {
                Name::ConstantValue(k)
            });
        }
        Err(self.expected(&format!("an instance name after '{}'", sigil as char)))
    }

    /// Decimal digits at the cursor (no white space skipped) as a u64; None if there are none.
    fn digits_u64(&mut self) -> R<Option<u64>> {
        let start = self.i;
        let mut n: u64 = 0;
        while let Some(&c) = self.b.get(self.i) {
            if !c.is_ascii_digit() {
                break;
            }
            n = n
                .checked_mul(10)
                .and_then(|n| n.checked_add(u64::from(c - b'0')))
                .ok_or_else(|| self.error_at(start, "instance number too large"))?;
            self.i += 1;
        }
        Ok((self.i > start).then_some(n))
    }

    /// An integer or a real: `[sign] digits [. digits [E [sign] digits]]`. As in ruststep,
    /// white space may follow a sign or the `E`. A leading `.5` or a lower-case `e` is
    /// accepted too.
    fn number(&mut self) -> R<Parameter> {
        let start = self.i;
        let mut spaced = false;
        let negative = self.b[self.i] == b'-';
        if matches!(self.b[self.i], b'+' | b'-') {
            self.i += 1;
            spaced |= self.spaces();
        }
        let int_start = self.i;
        self.digits();
        let int_digits = self.i - int_start;
        let mut real = false;
        // The fraction's digits and the exponent, for the fast path below.
        let (mut frac, mut exp) = (int_start..int_start, 0..0);
        let mut exp_negative = false;
        if self.b.get(self.i) == Some(&b'.') {
            real = true;
            self.i += 1;
            let frac_start = self.i;
            if int_digits == 0 && self.digits() == 0 {
                return Err(self.error_at(start, "a number without digits"));
            }
            self.digits();
            frac = frac_start..self.i;
            if matches!(self.b.get(self.i), Some(b'E' | b'e')) {
                let e = self.i;
                self.i += 1;
                spaced |= self.spaces();
                if matches!(self.b.get(self.i), Some(b'+' | b'-')) {
                    exp_negative = self.b[self.i] == b'-';
                    self.i += 1;
                    spaced |= self.spaces();
                }
                let exp_start = self.i;
                if self.digits() == 0 {
                    return Err(self.error_at(e, "an exponent without digits"));
                }
                exp = exp_start..self.i;
            }
        } else if int_digits == 0 {
            return Err(self.error_at(start, "a sign without a number"));
        }
        if real && !spaced {
            let int = &self.b[int_start..int_start + int_digits];
            let fast = fast_real(negative, int, &self.b[frac], exp_negative, &self.b[exp]);
            if let Some(x) = fast {
                return Ok(Parameter::Real(x));
            }
        }
        let raw = &self.text[start..self.i];
        let squeezed: String;
        let literal = if spaced {
            squeezed = raw.chars().filter(|c| !c.is_ascii_whitespace()).collect();
            squeezed.as_str()
        } else {
            raw
        };
        if real {
            let x: f64 = literal
                .parse()
                .map_err(|_| self.error_at(start, format!("bad real {literal}")))?;
            if !x.is_finite() {
                return Err(
                    self.error_at(start, format!("real {literal} is not finite (overflows)"))
                );
            }
            Ok(Parameter::Real(x))
        } else {
            literal
                .parse::<i64>()
                .map(Parameter::Integer)
                .map_err(|_| self.error_at(start, format!("integer {literal} is too large")))
        }
    }

    /// Skips white space inside a number (ruststep allows it after a sign and around an
    /// exponent's sign); true if there was some.
    fn spaces(&mut self) -> bool {
        let before = self.i;
        while self.b.get(self.i).is_some_and(|c| c.is_ascii_whitespace()) {
            self.i += 1;
        }
        self.i > before
    }

    /// Skips decimal digits; how many.
    fn digits(&mut self) -> usize {
        let before = self.i;
        while self.b.get(self.i).is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        self.i - before
    }

    /// `'…'` with `''` standing for one apostrophe. The cursor is on the opening quote.
    fn string(&mut self) -> R<String> {
        let start = self.i;
        self.i += 1;
        let mut out: Option<String> = None;
        let mut run = self.i;
        loop {
            match memchr_quote(&self.b[self.i..]) {
                None => return Err(self.error_at(start, "string is never closed")),
                Some(k) => {
                    let q = self.i + k;
                    if self.b.get(q + 1) == Some(&b'\'') {
                        out.get_or_insert_with(String::new)
                            .push_str(&self.text[run..=q]);
                        self.i = q + 2;
                        run = self.i;
                    } else {
                        self.i = q + 1;
                        let tail = &self.text[run..q];
                        return Ok(match out {
                            Some(mut s) => {
                                s.push_str(tail);
                                s
                            }
                            None => tail.to_string(),
                        });
                    }
                }
            }
        }
    }
}

/// A decimal real whose digits (at most 19, leading zeros included) make an integer `w` of
/// at most 2⁵³ and whose power of ten `e` (exponent less the fraction's digits) is within
/// ±22: then `w` and `10^|e|` are exact doubles and `w · 10^e` or `w / 10^−e` rounds once,
/// to the correctly rounded value that `str::parse` gives (Clinger's fast path, which
/// `str::parse` also takes, after more checks). `None` for any other real. The slices are
/// ASCII digits.
fn fast_real(
    negative: bool,
    int: &[u8],
    frac: &[u8],
    exp_negative: bool,
    exp: &[u8],
) -> Option<f64> {
    const POW10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    if int.len() + frac.len() > 19 || exp.len() > 4 {
        return None;
    }
    let mut w: u64 = 0;
    for &c in int.iter().chain(frac) {
        w = w * 10 + u64::from(c - b'0');
    }
    if w > 1 << 53 {
        return None;
    }
    let mut e: i32 = 0;
    for &c in exp {
        e = e * 10 + i32::from(c - b'0');
    }
    if exp_negative {
        e = -e;
    }
    let e = e - frac.len() as i32;
    let x = if w == 0 {
        0.0
    } else if (0..=22).contains(&e) {
        w as f64 * POW10[e as usize]
    } else if (-22..0).contains(&e) {
        w as f64 / POW10[(-e) as usize]
    } else {
        return None;
    };
    Some(if negative { -x } else { x })
}

fn memchr_quote(b: &[u8]) -> Option<usize> {
    b.iter().position(|&c| c == b'\'')
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::corpus_step_files;
    use truck_stepio::r#in::ruststep;

    fn head(data: &str) -> String {
        format!(
            "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n"
        )
    }

    fn entities(data: &str) -> Vec<EntityInstance> {
        parse(&head(data), 64)
            .unwrap()
            .data_sections()
            .remove(0)
            .entities
    }

    fn err(text: &str) -> SyntaxError {
        parse(text, 64).unwrap_err()
    }

    /// Every sample and real-world STEP file gives the same AST as ruststep's own parser.
    #[test]
    fn same_ast_as_ruststep_on_every_file() {
        for f in corpus_step_files() {
            let text = std::fs::read_to_string(&f).unwrap();
            let ours = parse(&text, 64).unwrap_or_else(|e| panic!("{f:?}: {e}"));
            let theirs = ruststep::parser::parse(&text).unwrap();
            assert_eq!(ours.header, theirs.header, "{f:?}");
            assert_eq!(ours.data_sections(), theirs.data, "{f:?}");
        }
    }

    /// Points and directions in the usual form are kept compact; every other form goes the
    /// general way. Either way the records are ruststep's.
    #[test]
    fn points_in_the_usual_form_are_compact() {
        let data = "#1=CARTESIAN_POINT('',(1.,-2.5,3.E1));
            #2 = DIRECTION ( 'a b' , ( 0. , 1. ) ) ;
            #3=CARTESIAN_POINT('',(-0.5));
            #4=CARTESIAN_POINT($,(1.,2.,3.));
            #5=CARTESIAN_POINT('',(1,2,3));
            #6=CARTESIAN_POINT('',(1.,2.,3.,4.));
            #7=CARTESIAN_POINT('',/* c */(1.,2.,3.));
            #8=DIRECTION('',(1.,
                0.,0.));
            #9=DIRECTIONS('',(1.,0.,0.));
            #10=CARTESIAN_POINT('',(.T.));
            #11=CARTESIAN_POINT('',(1.,#2,3.));
            #12=(CARTESIAN_POINT('',(1.,2.,3.)));
            #13=CARTESIAN_POINT('',(1.,2.,3.))/* c */;";
        let text = head(data);
        let parsed = parse(&text, 64).unwrap();
        let compact: Vec<u64> = parsed.data[0]
            .entities
            .iter()
            .filter(|item| matches!(item, Item::Point(_)))
            .map(Item::id)
            .collect();
        assert_eq!(compact, vec![1, 2, 3, 8]);
        let Item::Point(p) = &parsed.data[0].entities[1] else {
            panic!()
        };
        assert_eq!(
            (p.kind, p.label.as_str(), p.coords()),
            (PointKind::Direction, "a b", &[0.0, 1.0][..])
        );
        let theirs = ruststep::parser::parse(&text).unwrap();
        assert_eq!(parsed.data_sections(), theirs.data);
        // ruststep refuses `''`, which the standard allows.
        let e = entities("#1=CARTESIAN_POINT('it''s',(1.));");
        assert_eq!(
            e[0],
            Item::Point(CompactPoint::new(
                1,
                PointKind::CartesianPoint,
                "it's".into(),
                &[1.0]
            ))
            .to_instance()
        );
        // Too little nesting allowed for the coordinate list: the general reader's error.
        let text =
            "ISO-10303-21;HEADER;ENDSEC;DATA;#1=CARTESIAN_POINT('',(1.));ENDSEC;END-ISO-10303-21;";
        let e = parse(text, 1).unwrap_err();
        assert!(e.message.contains("nested more than 1"), "{e}");
        assert!(parse(text, 2).is_ok());
        // A malformed point gets the general reader's message.
        let e = err(&head("#1=CARTESIAN_POINT('',(1.,2.,3.)"));
        assert!(e.message.contains("expected ',' or ')'"), "{e}");
        let e = err(&head("#1=CARTESIAN_POINT('',(1.,2.,3.))"));
        assert!(e.message.contains("at the end of #1"), "{e}");
        let e = err(&head("#1=CARTESIAN_POINT('',(1.,2.E,3.));"));
        assert!(e.message.contains("exponent without digits"), "{e}");
    }

    /// The fast path for reals gives `str::parse`'s double, bit for bit, where it answers;
    /// it answers for the usual CAD literals.
    #[test]
    fn fast_reals_are_parse_s_reals() {
        let check = |lit: &str| -> bool {
            let negative = lit.starts_with('-');
            let body = lit.trim_start_matches(['+', '-']);
            let (mantissa, exp) = body.split_once(['E', 'e']).unwrap_or((body, ""));
            let (exp_negative, exp) = match exp.strip_prefix('-') {
                Some(e) => (true, e),
                None => (false, exp.trim_start_matches('+')),
            };
            let (int, frac) = mantissa.split_once('.').expect("a real");
            let fast = fast_real(
                negative,
                int.as_bytes(),
                frac.as_bytes(),
                exp_negative,
                exp.as_bytes(),
            );
            if let Some(x) = fast {
                let std: f64 = lit.parse().expect("std parses it");
                assert_eq!(x.to_bits(), std.to_bits(), "{lit}");
            }
            fast.is_some()
        };
        for lit in [
            "4.886817528445",
            "-0.",
            "0.E0",
            "-3.25E0",
            "1.E-22",
            "1.E22",
            "123.456E-7",
            "9007199254740992.",
            "-.5",
        ] {
            assert!(check(lit), "{lit} takes the fast path");
        }
        for lit in [
            "9007199254740993.",
            "1.E23",
            "1.E-23",
            "0.12345678901234567890",
            "1.E99999",
            "1.7976931348623157E308",
        ] {
            assert!(!check(lit), "{lit} does not");
        }
        // A deterministic spread of literals: sign, digits before and after the point,
        // exponent.
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let mut fast = 0;
        for _ in 0..200_000 {
            let digits = |n: u64, next: &mut dyn FnMut(u64) -> u64| -> String {
                (0..n).map(|_| char::from(b'0' + next(10) as u8)).collect()
            };
            let sign = ["", "-", "+"][next(3) as usize];
            let int = digits(next(12), &mut next);
            let frac = digits(next(12), &mut next);
            let exp = match next(3) {
                0 => String::new(),
                _ => format!("E{}", next(61) as i64 - 30),
            };
            let lit = format!("{sign}{int}.{frac}{exp}");
            if int.is_empty() && frac.is_empty() {
                continue;
            }
            fast += usize::from(check(&lit));
        }
        assert!(fast > 50_000, "{fast}");
    }

    #[test]
    fn parameters() {
        let e = entities(
            "#1=A(1,-2,+3.5,-.5E-1,1.E - 2,'x''y',$,*,.T.,#12,@3,(),((1),(2.)),LENGTH_MEASURE(2.),!USER(- 4));",
        );
        let EntityInstance::Simple { id: 1, record } = &e[0] else {
            panic!("{e:?}")
        };
        assert_eq!(record.name, "A");
        use Parameter as P;
        assert_eq!(
            record.parameter,
            P::List(vec![
                P::Integer(1),
                P::Integer(-2),
                P::Real(3.5),
                P::Real(-0.05),
                P::Real(0.01),
                P::String("x'y".into()),
                P::NotProvided,
                P::Omitted,
                P::Enumeration("T".into()),
                P::Ref(Name::Entity(12)),
                P::Ref(Name::Value(3)),
                P::List(vec![]),
                P::List(vec![
                    P::List(vec![P::Integer(1)]),
                    P::List(vec![P::Real(2.0)])
                ]),
                P::Typed {
                    keyword: "LENGTH_MEASURE".into(),
                    parameter: Box::new(P::Real(2.0))
                },
                P::Typed {
                    keyword: "USER".into(),
                    parameter: Box::new(P::Integer(-4))
                },
            ])
        );
    }

    #[test]
    fn complex_instances_comments_and_layout() {
        let e = entities(
            "/* a comment; with 'quotes' */ #7 = ( A ( ) B(1) /* inner */ ) ;\r\n#8=\n C (\n'multi\nline', 2.5E+3 );",
        );
        assert_eq!(e.len(), 2);
        let EntityInstance::Complex { id: 7, subsuper } = &e[0] else {
            panic!("{e:?}")
        };
        assert_eq!(subsuper.0.len(), 2);
        assert_eq!(subsuper.0[1].name, "B");
        let EntityInstance::Simple { id: 8, record } = &e[1] else {
            panic!("{e:?}")
        };
        assert_eq!(
            record.parameter,
            Parameter::List(vec![
                Parameter::String("multi\nline".into()),
                Parameter::Real(2500.0)
            ])
        );
    }

    #[test]
    fn skipped_sections() {
        let text = head("#1=A(1);").replace(
            "DATA;",
            "ANCHOR;\n<x> = #1;\nENDSEC;\nREFERENCE;\n#9 = <a.stp#x>;\nENDSEC;\nDATA;",
        ) + "SIGNATURE;\nQUJD\nENDSEC;\n";
        // The signature comes after the end marker, which ends the parse.
        let ex = parse(&text, 64).unwrap();
        assert_eq!(ex.data[0].entities.len(), 1);
    }

    #[test]
    fn errors_give_line_and_column() {
        let e = err(&head("#1=A(1,2;"));
        assert_eq!((e.line, e.column), (8, 9), "{e}");
        assert!(e.message.contains("expected ',' or ')'"), "{e}");

        let e = err(&head("#1=A('open);"));
        assert!(e.message.contains("string is never closed"), "{e}");
        assert_eq!(e.line, 8);

        let e = err(&head("#1=A(99999999999999999999);"));
        assert!(e.message.contains("too large"), "{e}");
        let e = err(&head("#99999999999999999999=A(1);"));
        assert!(e.message.contains("too large"), "{e}");
        let e = err(&head("#1=A(1.0E999);"));
        assert!(e.message.contains("not finite"), "{e}");
        let e = err(&head("#1=A(\"0FF\");"));
        assert!(e.message.contains("binary"), "{e}");
        let e = err(&head("#1=a(1);"));
        assert!(e.message.contains("keyword"), "{e}");
        let e = err(&head("/* never closed"));
        assert!(e.message.contains("comment"), "{e}");
        let e = err(&head("#1=A(1);").replace("END-ISO-10303-21;\n", ""));
        assert!(e.message.contains("truncated"), "{e}");
        let e = err("solid cube\n");
        assert!(e.message.contains("not a STEP file"), "{e}");
        let e = err(&head("#1=(  );"));
        assert!(e.message.contains("empty complex"), "{e}");
        // Column counts characters, not bytes.
        let e = err(&head("#1=A('é',;"));
        assert_eq!((e.line, e.column), (8, 10), "{e}");
    }

    /// The instance list is sized from the semicolons to come, but not beyond the cap: a
    /// comment full of them reserves no more than that.
    #[test]
    fn the_instance_list_reservation_is_capped() {
        let text = head(&format!("/* {} */ #1=A(1);", ";".repeat(4_000_000)));
        let parsed = parse(&text, 64).unwrap();
        let entities = &parsed.data[0].entities;
        assert_eq!(entities.len(), 1);
        assert!(
            entities.capacity() <= MAX_RESERVED_INSTANCES,
            "{}",
            entities.capacity()
        );
        let few = parse(&head("#1=A(1);#2=A(2);"), 64).unwrap();
        assert!(few.data[0].entities.capacity() <= 4);
    }

    #[test]
    fn nesting_is_bounded_without_recursion_overflow() {
        let deep = format!("#1=A({}1{});", "(".repeat(100_000), ")".repeat(100_000));
        let e = err(&head(&deep));
        assert!(e.message.contains("nested more than 64"), "{e}");
        let ok = format!("#1=A({}1{});", "(".repeat(62), ")".repeat(62));
        assert_eq!(entities(&ok).len(), 1);
    }
}
