//! Unique names for scene elements (materials, meshes) merged from several files.

/// `base`, or `base#2`, `base#3`, ... : the first that `taken` rejects.
pub fn unique_name(base: &str, taken: impl Fn(&str) -> bool) -> String {
    if !taken(base) {
        return base.to_owned();
    }
    (2..).map(|i| format!("{base}#{i}")).find(|n| !taken(n)).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unique_names() {
        assert_eq!(unique_name("a", |_| false), "a");
        assert_eq!(unique_name("a", |n| n == "a" || n == "a#2"), "a#3");
    }
}
