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
//! Semantics otherwise follow ruststep (the tests compare both on every sample): keywords as
//! written (a user-defined `!NAME` loses its `!`), `.T.` is an enumeration, strings are kept
//! undecoded but for `''` → `'`, and `ANCHOR`, `REFERENCE` and `SIGNATURE` sections are read
//! over and dropped (truck reads none of them).

use truck_stepio::r#in::ruststep::ast::{
    DataSection, EntityInstance, Exchange, Name, Parameter, Record, SubSuperRecord,
};

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
pub fn parse(text: &str, max_nesting: usize) -> Result<Exchange, SyntaxError> {
    let mut p = Parser {
        text,
        b: text.as_bytes(),
        i: 0,
        depth: 0,
        max_nesting,
    };
    p.exchange()
}

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

    fn exchange(&mut self) -> R<Exchange> {
        if self.text.starts_with('\u{feff}') {
            self.i = '\u{feff}'.len_utf8();
        }
        if self.word()? != "ISO-10303-21" {
            return Err(self.error_at(0, "does not start with ISO-10303-21; (not a STEP file)"));
        }
        self.expect(b';', || "after ISO-10303-21")?;
        let mut ex = Exchange {
            header: vec![],
            anchor: vec![],
            reference: vec![],
            data: vec![],
            signature: vec![],
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
                        let list = self.list_items()?;
                        self.depth -= 1;
                        list
                    } else {
                        vec![]
                    };
                    self.expect(b';', || "after DATA")?;
                    let mut entities = Vec::new();
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
                    ex.data.push(DataSection { meta, entities });
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

    fn instance(&mut self) -> R<EntityInstance> {
        let at = self.i;
        self.i += 1; // '#'
        let id = self
            .digits_u64()?
            .ok_or_else(|| self.expected("an entity id after '#'"))?;
        self.expect(b'=', || format!("after #{id}"))?;
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
        Ok(inst)
    }

    /// `KEYWORD ( parameters )`; the parameters become one list parameter, as in ruststep.
    fn record(&mut self) -> R<Record> {
        let name = self.keyword()?;
        self.expect(b'(', || format!("after {name}"))?;
        self.open()?;
        let params = self.list_items()?;
        self.depth -= 1;
        Ok(Record {
            name,
            parameter: Parameter::List(params),
        })
    }

    /// Comma-separated parameters up to and including the closing ')'. The '(' is read.
    fn list_items(&mut self) -> R<Vec<Parameter>> {
        let mut items = Vec::new();
        if self.eat(b')')? {
            return Ok(items);
        }
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
                let items = self.list_items()?;
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
        if matches!(self.b[self.i], b'+' | b'-') {
            self.i += 1;
            spaced |= self.spaces();
        }
        let int_start = self.i;
        self.digits();
        let int_digits = self.i - int_start;
        let mut real = false;
        if self.b.get(self.i) == Some(&b'.') {
            real = true;
            self.i += 1;
            if int_digits == 0 && self.digits() == 0 {
                return Err(self.error_at(start, "a number without digits"));
            }
            self.digits();
            if matches!(self.b.get(self.i), Some(b'E' | b'e')) {
                let e = self.i;
                self.i += 1;
                spaced |= self.spaces();
                if matches!(self.b.get(self.i), Some(b'+' | b'-')) {
                    self.i += 1;
                    spaced |= self.spaces();
                }
                if self.digits() == 0 {
                    return Err(self.error_at(e, "an exponent without digits"));
                }
            }
        } else if int_digits == 0 {
            return Err(self.error_at(start, "a sign without a number"));
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

fn memchr_quote(b: &[u8]) -> Option<usize> {
    b.iter().position(|&c| c == b'\'')
}

#[cfg(test)]
mod tests {
    use super::*;
    use truck_stepio::r#in::ruststep;

    fn head(data: &str) -> String {
        format!(
            "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('x','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n"
        )
    }

    fn entities(data: &str) -> Vec<EntityInstance> {
        parse(&head(data), 64).unwrap().data.remove(0).entities
    }

    fn err(text: &str) -> SyntaxError {
        parse(text, 64).unwrap_err()
    }

    /// Every sample and real-world STEP file gives the same AST as ruststep's own parser.
    #[test]
    fn same_ast_as_ruststep_on_every_file() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut files = vec![];
        for dir in [root.join("samples"), root.join("../shared/realworld")] {
            for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
                let p = e.path();
                let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
                if ["step", "stp", "STEP", "STP"].contains(&ext) {
                    files.push(p);
                }
            }
        }
        assert!(files.len() >= 30, "found only {} files", files.len());
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            let ours = parse(&text, 64).unwrap_or_else(|e| panic!("{f:?}: {e}"));
            let theirs = ruststep::parser::parse(&text).unwrap();
            assert_eq!(ours.header, theirs.header, "{f:?}");
            assert_eq!(ours.data, theirs.data, "{f:?}");
        }
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

    #[test]
    fn nesting_is_bounded_without_recursion_overflow() {
        let deep = format!("#1=A({}1{});", "(".repeat(100_000), ")".repeat(100_000));
        let e = err(&head(&deep));
        assert!(e.message.contains("nested more than 64"), "{e}");
        let ok = format!("#1=A({}1{});", "(".repeat(62), ")".repeat(62));
        assert_eq!(entities(&ok).len(), 1);
    }
}
