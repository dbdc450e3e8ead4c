//! A small parser for the generated Rust source, to read the arrays back.
//!
//! It accepts exactly what the generator is meant to write: `//` comments,
//! `///` doc comments and items `pub static|const NAME: TYPE = VALUE;`,
//! where VALUE is built from arrays, tuples, calls of paths, integers,
//! floats, string literals and paths. Anything else is a parse error, so a
//! test that parses the whole output also checks its structure.

#![allow(dead_code)]

use std::collections::BTreeMap;

use microraster_import::Model;

/// A parsed value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// `[a, b, ...]`
    Array(Vec<Value>),
    /// `(a, b, ...)`
    Tuple(Vec<Value>),
    /// `path(args)`
    Call(String, Vec<Value>),
    /// A path such as `None`.
    Path(String),
    /// An integer literal (decimal or hex), with its sign.
    Int(i64),
    /// A float literal.
    Float(f64),
    /// A string literal, unescaped.
    Str(String),
}

/// One item: `static` or `const`, its type as written, its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    pub kind: String,
    pub ty: String,
    pub value: Value,
}

struct P<'a> {
    s: &'a [u8],
    i: usize,
}

impl P<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }
    fn eat(&mut self, t: &str) -> bool {
        self.ws();
        if self.s[self.i..].starts_with(t.as_bytes()) {
            self.i += t.len();
            true
        } else {
            false
        }
    }
    fn expect(&mut self, t: &str) -> Result<(), String> {
        if self.eat(t) {
            Ok(())
        } else {
            Err(format!("expected `{t}` at {}", self.context()))
        }
    }
    fn context(&self) -> String {
        let end = (self.i + 40).min(self.s.len());
        format!(
            "{}: {:?}",
            self.i,
            String::from_utf8_lossy(&self.s[self.i..end])
        )
    }
    fn ident(&mut self) -> Result<String, String> {
        self.ws();
        let start = self.i;
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
        {
            self.i += 1;
        }
        if start == self.i || self.s[start].is_ascii_digit() {
            return Err(format!("expected an identifier at {}", self.context()));
        }
        Ok(String::from_utf8_lossy(&self.s[start..self.i]).into_owned())
    }
    fn path(&mut self) -> Result<String, String> {
        let mut p = String::new();
        if self.eat("::") {
            p.push_str("::");
        }
        p.push_str(&self.ident()?);
        while self.eat("::") {
            p.push_str("::");
            p.push_str(&self.ident()?);
        }
        Ok(p)
    }
    fn list(&mut self, close: &str) -> Result<Vec<Value>, String> {
        let mut items = Vec::new();
        loop {
            if self.eat(close) {
                return Ok(items);
            }
            items.push(self.value()?);
            if !self.eat(",") {
                self.expect(close)?;
                return Ok(items);
            }
        }
    }
    fn value(&mut self) -> Result<Value, String> {
        match self.peek() {
            Some(b'[') => {
                self.i += 1;
                Ok(Value::Array(self.list("]")?))
            }
            Some(b'(') => {
                self.i += 1;
                Ok(Value::Tuple(self.list(")")?))
            }
            Some(b'"') => self.string(),
            Some(c) if c == b'-' || c.is_ascii_digit() => self.number(),
            Some(_) => {
                let p = self.path()?;
                if self.eat("(") {
                    Ok(Value::Call(p, self.list(")")?))
                } else {
                    Ok(Value::Path(p))
                }
            }
            None => Err("unexpected end".to_string()),
        }
    }
    fn number(&mut self) -> Result<Value, String> {
        let start = self.i;
        if self.s[self.i] == b'-' {
            self.i += 1;
        }
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_alphanumeric()
                || self.s[self.i] == b'.'
                || (self.s[self.i] == b'-' && self.s[self.i - 1] == b'e'))
        {
            self.i += 1;
        }
        let t = String::from_utf8_lossy(&self.s[start..self.i]).into_owned();
        let (neg, body) = match t.strip_prefix('-') {
            Some(b) => (true, b),
            None => (false, t.as_str()),
        };
        if let Some(hex) = body.strip_prefix("0x") {
            let v = i64::from_str_radix(hex, 16).map_err(|e| format!("{t}: {e}"))?;
            return Ok(Value::Int(if neg { -v } else { v }));
        }
        if body.contains(['.', 'e']) {
            return t
                .parse::<f64>()
                .map(Value::Float)
                .map_err(|e| format!("{t}: {e}"));
        }
        t.parse::<i64>()
            .map(Value::Int)
            .map_err(|e| format!("{t}: {e}"))
    }
    fn string(&mut self) -> Result<Value, String> {
        self.i += 1;
        let mut out = String::new();
        let text = std::str::from_utf8(&self.s[self.i..]).map_err(|e| e.to_string())?;
        let mut chars = text.char_indices();
        while let Some((k, c)) = chars.next() {
            match c {
                '"' => {
                    self.i += k + 1;
                    return Ok(Value::Str(out));
                }
                '\\' => match chars.next().map(|x| x.1) {
                    Some('n') => out.push('\n'),
                    Some('r') => out.push('\r'),
                    Some('t') => out.push('\t'),
                    Some('0') => out.push('\0'),
                    Some('\\') => out.push('\\'),
                    Some('"') => out.push('"'),
                    Some('\'') => out.push('\''),
                    Some('u') => {
                        let rest: String = chars
                            .by_ref()
                            .map(|x| x.1)
                            .take_while(|&c| c != '}')
                            .collect();
                        let hex = rest.trim_start_matches('{');
                        let v = u32::from_str_radix(hex, 16).map_err(|e| e.to_string())?;
                        out.push(char::from_u32(v).ok_or("bad escape")?);
                    }
                    other => return Err(format!("unknown escape {other:?}")),
                },
                c => out.push(c),
            }
        }
        Err("unterminated string".to_string())
    }
}

/// Parses a whole generated file into its items, by name.
pub fn parse_items(text: &str) -> Result<BTreeMap<String, Item>, String> {
    let mut items = BTreeMap::new();
    let mut p = P {
        s: text.as_bytes(),
        i: 0,
    };
    loop {
        match p.peek() {
            None => return Ok(items),
            Some(b'/') => {
                if !p.eat("//") {
                    return Err(format!("stray `/` at {}", p.context()));
                }
                while p.i < p.s.len() && p.s[p.i] != b'\n' {
                    p.i += 1;
                }
            }
            Some(_) => {
                p.expect("pub")?;
                let kind = p.ident()?;
                if kind != "static" && kind != "const" {
                    return Err(format!("unexpected `{kind}`"));
                }
                let name = p.ident()?;
                p.expect(":")?;
                // The type: everything up to ` = ` at bracket depth 0.
                p.ws();
                let start = p.i;
                let mut depth = 0i32;
                while p.i < p.s.len() && !(depth == 0 && p.s[p.i] == b'=') {
                    match p.s[p.i] {
                        b'[' | b'(' | b'<' => depth += 1,
                        b']' | b')' | b'>' => depth -= 1,
                        _ => {}
                    }
                    p.i += 1;
                }
                let ty = String::from_utf8_lossy(&p.s[start..p.i]).trim().to_string();
                p.expect("=")?;
                let value = p.value()?;
                p.expect(";")?;
                if items
                    .insert(name.clone(), Item { kind, ty, value })
                    .is_some()
                {
                    return Err(format!("{name} defined twice"));
                }
            }
        }
    }
}

/// The length an array type declares: the `N` of `[T; N]`.
pub fn declared_len(ty: &str) -> usize {
    let inner = ty
        .strip_prefix('[')
        .and_then(|t| t.strip_suffix(']'))
        .expect(ty);
    inner.rsplit(';').next().unwrap().trim().parse().expect(ty)
}

impl Value {
    pub fn array(&self) -> &[Value] {
        match self {
            Value::Array(v) => v,
            other => panic!("not an array: {other:?}"),
        }
    }
    pub fn int(&self) -> i64 {
        match self {
            Value::Int(v) => *v,
            other => panic!("not an integer: {other:?}"),
        }
    }
    pub fn float(&self) -> f64 {
        match self {
            Value::Float(v) => *v,
            other => panic!("not a float: {other:?}"),
        }
    }
    /// The argument of a one-argument call of `path`.
    pub fn call(&self, path: &str) -> &[Value] {
        match self {
            Value::Call(p, args) if p == path => args,
            other => panic!("not a call of {path}: {other:?}"),
        }
    }
}

/// The standard CRC-32 of PNG chunks (the tests damage PNGs and fix up
/// their checksums, or build chunks by hand).
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Checks the cluster layout of `m` against every rule of
/// `microraster::mesh::Mesh::with_clusters` and the importer's own: none
/// without [`ObjOptions::cluster_triangles`](microraster_import::ObjOptions),
/// otherwise 1 to that many triangles each, tiling every group's triangles
/// in order; vertex runs that tile the vertices in order, in the order the
/// cluster's triangles first use them; tight boxes.
pub fn check_clusters(m: &Model) {
    let max = m.options.cluster_triangles;
    if max == 0 {
        assert!(m.clusters.is_empty());
        assert!(m.groups.iter().all(|g| g.clusters.is_empty()));
        assert!(m.cluster_bounds_fixed().is_empty());
        return;
    }
    let mut next_cluster = 0;
    for g in &m.groups {
        assert_eq!(g.clusters.start, next_cluster, "{g:?}");
        assert!(g.clusters.end <= m.clusters.len(), "{g:?}");
        let clusters = &m.clusters[g.clusters.clone()];
        // Within the group, and (with the tiling below) all of it.
        assert_eq!(clusters.is_empty(), g.triangles.is_empty(), "{g:?}");
        if let (Some(first), Some(last)) = (clusters.first(), clusters.last()) {
            assert_eq!(first.triangles.start, g.triangles.start);
            assert_eq!(last.triangles.end, g.triangles.end);
        }
        // Full clusters, but for the group's last.
        for c in clusters.iter().rev().skip(1) {
            assert_eq!(c.triangles.len(), max, "{g:?}: {c:?}");
        }
        next_cluster = g.clusters.end;
    }
    assert_eq!(next_cluster, m.clusters.len());

    let fixed = m.positions_fixed();
    let bounds = m.cluster_bounds_fixed();
    assert_eq!(bounds.len(), m.clusters.len());
    let (mut next_triangle, mut next_vertex) = (0, 0);
    for (k, (c, b)) in m.clusters.iter().zip(&bounds).enumerate() {
        assert_eq!(c.triangles.start, next_triangle, "cluster {k}");
        assert!((1..=max).contains(&c.triangles.len()), "cluster {k}: {c:?}");
        assert_eq!(c.vertices.start, next_vertex, "cluster {k}");
        // Every index inside the run, new vertices numbered in first-use
        // order, and every vertex of the run used.
        let mut unused = c.vertices.start;
        for t in &m.triangles[c.triangles.clone()] {
            for &i in t {
                let i = i as usize;
                assert!(c.vertices.contains(&i), "cluster {k}: {t:?} {c:?}");
                if i == unused {
                    unused += 1;
                } else {
                    assert!(i < unused, "cluster {k}: {i} before {unused}");
                }
            }
        }
        assert_eq!(unused, c.vertices.end, "cluster {k}");
        // The box is the smallest that holds the run's generated positions,
        // so it holds them all.
        let run = &fixed[c.vertices.clone()];
        let lo: [i32; 3] = std::array::from_fn(|a| run.iter().map(|p| p[a]).min().unwrap());
        let hi: [i32; 3] = std::array::from_fn(|a| run.iter().map(|p| p[a]).max().unwrap());
        assert_eq!(*b, [lo, hi], "cluster {k}");
        next_triangle = c.triangles.end;
        next_vertex = c.vertices.end;
    }
    assert_eq!(next_triangle, m.triangles.len());
    assert_eq!(next_vertex, m.positions.len());
}

/// An OBJ file of one face: a regular, convex polygon of `n` corners on the
/// unit circle in the z = 0 plane, counter-clockwise.
pub fn regular_polygon_obj(n: usize) -> String {
    let mut src = String::new();
    for k in 0..n {
        let a = k as f64 * std::f64::consts::TAU / n as f64;
        src += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    src += "f";
    for k in 1..=n {
        src += &format!(" {k}");
    }
    src + "\n"
}
