//! The logical lines of an OBJ or MTL file.

/// Logical lines: comments stripped, `\` continuations joined, with the
/// 1-based number of each one's first physical line.
pub(super) struct Lines<'a> {
    physical: std::iter::Enumerate<std::str::Split<'a, char>>,
}

impl<'a> Lines<'a> {
    pub(super) fn new(source: &'a str) -> Self {
        // Editors on Windows save UTF-8 with a byte-order mark; left in, it
        // would glue onto the first keyword and that statement be ignored.
        let source = source.strip_prefix('\u{FEFF}').unwrap_or(source);
        Self {
            physical: source.split('\n').enumerate(),
        }
    }
}

impl Iterator for Lines<'_> {
    type Item = (usize, String);

    fn next(&mut self) -> Option<(usize, String)> {
        let mut logical = String::new();
        let mut start = None;
        for (i, raw) in self.physical.by_ref() {
            start.get_or_insert(i + 1);
            let content = match raw.find('#') {
                Some(p) => &raw[..p],
                None => raw,
            };
            let content = content.trim_end();
            match content.strip_suffix('\\') {
                Some(head) => {
                    logical.push_str(head);
                    logical.push(' ');
                }
                None => {
                    logical.push_str(content);
                    return Some((start.unwrap_or(i + 1), logical));
                }
            }
        }
        start.map(|line| (line, logical))
    }
}
