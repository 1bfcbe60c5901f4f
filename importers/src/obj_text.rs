//! Line-level text of OBJ and MTL files: line terminators and trailing comments, shared by the
//! checks of [`obj_lint`](crate::obj_lint) and the stream handed to `tobj`.

use std::io::{BufRead, Read};

/// A line without its trailing comment: from the first `#` that starts the line or follows
/// whitespace (`Ka 0.63 0.065 0.05 # Red`, `v 1 2 3 # from CAD`), as tolerant readers
/// (Blender's, tinyobjloader's) accept them; a `#` inside a word (`usemtl paint#2`) is kept.
pub(crate) fn strip_comment(line: &str) -> &str {
    let b = line.as_bytes();
    for (i, &c) in b.iter().enumerate() {
        if c == b'#' && (i == 0 || b[i - 1].is_ascii_whitespace()) {
            return &line[..i];
        }
    }
    line
}

/// A reader of an OBJ stream with [`strip_comment`] applied to every line (line count and
/// terminators kept), for `tobj`, which reads trailing comments as values.
pub(crate) struct CommentFree<R> {
    inner: R,
    line: Vec<u8>,
    pos: usize,
}

impl<R: BufRead> CommentFree<R> {
    /// Wraps `inner`.
    pub(crate) fn new(inner: R) -> Self {
        Self { inner, line: Vec::new(), pos: 0 }
    }
}

impl<R: BufRead> Read for CommentFree<R> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        if self.pos == self.line.len() {
            self.line.clear();
            self.pos = 0;
            if self.inner.read_until(b'\n', &mut self.line)? == 0 {
                return Ok(0);
            }
            let body = strip_eol(&self.line).len();
            let cut = match std::str::from_utf8(&self.line[..body]) {
                Ok(text) => strip_comment(text).len(),
                Err(_) => body, // the OBJ check has refused non-UTF-8 lines already
            };
            if cut < body {
                self.line.drain(cut..body);
            }
        }
        let n = out.len().min(self.line.len() - self.pos);
        out[..n].copy_from_slice(&self.line[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

/// Removes the line terminator the way `BufRead::lines` does ("\n" or "\r\n").
pub(crate) fn strip_eol(mut b: &[u8]) -> &[u8] {
    if let Some(r) = b.strip_suffix(b"\n") {
        b = r;
        if let Some(r) = b.strip_suffix(b"\r") {
            b = r;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_are_cut_where_they_start_a_word() {
        assert_eq!(strip_comment("Ka 0.63 0.065 0.05 # Red"), "Ka 0.63 0.065 0.05 ");
        assert_eq!(strip_comment("# whole line"), "");
        assert_eq!(strip_comment("v 1 2 3\t#x"), "v 1 2 3\t");
        assert_eq!(strip_comment("usemtl paint#2"), "usemtl paint#2");
    }

    #[test]
    fn the_stream_keeps_lines_and_terminators() {
        let text = "v 0 0 0 # a\r\nf 1 2 3\n# only\nusemtl x#1 # c";
        let mut out = String::new();
        CommentFree::new(text.as_bytes()).read_to_string(&mut out).unwrap();
        assert_eq!(out, "v 0 0 0 \r\nf 1 2 3\n\nusemtl x#1 ");
    }
}
