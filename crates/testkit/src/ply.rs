//! PLY files written byte by byte, with any header and any property types, in ASCII or
//! binary (both byte orders): for the tests of the PLY reader.

/// PLY encodings for [`PlyBuilder`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enc {
    /// `format ascii 1.0`.
    Ascii,
    /// `format binary_little_endian 1.0`.
    Le,
    /// `format binary_big_endian 1.0`.
    Be,
}

/// Writes PLY files by hand, with any header and any property types, to test readers.
pub struct PlyBuilder {
    enc: Enc,
    header: Vec<String>,
    body: Vec<u8>,
    first_in_line: bool,
}

impl PlyBuilder {
    /// The `ply` and `format` lines of a file in encoding `enc`, and no element yet.
    pub fn new(enc: Enc) -> Self {
        let format = match enc {
            Enc::Ascii => "ascii",
            Enc::Le => "binary_little_endian",
            Enc::Be => "binary_big_endian",
        };
        Self {
            enc,
            header: vec!["ply".into(), format!("format {format} 1.0")],
            body: Vec::new(),
            first_in_line: true,
        }
    }
    /// Adds a raw header line.
    pub fn line(mut self, line: &str) -> Self {
        self.header.push(line.into());
        self
    }
    /// Adds an `element NAME COUNT` header line.
    pub fn element(self, name: &str, count: usize) -> Self {
        self.line(&format!("element {name} {count}"))
    }
    /// Adds a `property TYPE NAME` header line.
    pub fn property(self, ty: &str, name: &str) -> Self {
        self.line(&format!("property {ty} {name}"))
    }
    /// Adds a `property list COUNT ITEM NAME` header line.
    pub fn list_property(self, count: &str, item: &str, name: &str) -> Self {
        self.line(&format!("property list {count} {item} {name}"))
    }
    /// Appends one value of type `ty` (a PLY type name, as `float` or `uint8`).
    ///
    /// # Panics
    /// For an unknown type in a binary encoding.
    pub fn value(&mut self, ty: &str, v: f64) -> &mut Self {
        match self.enc {
            Enc::Ascii => {
                if !self.first_in_line {
                    self.body.push(b' ');
                }
                let text = match ty {
                    "float" | "float32" | "double" | "float64" => format!("{v}"),
                    _ => format!("{}", v as i64),
                };
                self.body.extend(text.as_bytes());
                self.first_in_line = false;
            }
            Enc::Le | Enc::Be => {
                let le = self.enc == Enc::Le;
                macro_rules! put {
                    ($x:expr) => {{
                        let x = $x;
                        self.body
                            .extend(if le { x.to_le_bytes() } else { x.to_be_bytes() })
                    }};
                }
                match ty {
                    "char" | "int8" => put!(v as i8),
                    "uchar" | "uint8" => put!(v as u8),
                    "short" | "int16" => put!(v as i16),
                    "ushort" | "uint16" => put!(v as u16),
                    "int" | "int32" => put!(v as i32),
                    "uint" | "uint32" => put!(v as u32),
                    "float" | "float32" => put!(v as f32),
                    "double" | "float64" => put!(v),
                    other => panic!("unknown type {other}"),
                }
            }
        }
        self
    }
    /// Appends a list: its length as `count`, then the items as `item`.
    pub fn list(&mut self, count: &str, item: &str, items: &[f64]) -> &mut Self {
        self.value(count, items.len() as f64);
        for &x in items {
            self.value(item, x);
        }
        self
    }
    /// Ends an element (a line in ASCII).
    pub fn end(&mut self) -> &mut Self {
        if self.enc == Enc::Ascii {
            self.body.push(b'\n');
            self.first_in_line = true;
        }
        self
    }
    /// The file: the header, `end_header`, then the body.
    pub fn bytes(&self) -> Vec<u8> {
        let mut out = self.header.join("\n").into_bytes();
        out.extend(b"\nend_header\n");
        out.extend(&self.body);
        out
    }
}

/// A binary or ASCII PLY of a unit square split into two triangles, with float `x y z`,
/// a `uchar int` face list, and `extra` header lines / values left to the caller.
pub fn square(enc: Enc) -> PlyBuilder {
    let mut b = PlyBuilder::new(enc)
        .element("vertex", 4)
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .element("face", 2)
        .list_property("uchar", "int", "vertex_indices");
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            b.value("float", c);
        }
        b.end();
    }
    b.list("uchar", "int", &[0.0, 1.0, 2.0]).end();
    b.list("uchar", "int", &[0.0, 2.0, 3.0]).end();
    b
}
