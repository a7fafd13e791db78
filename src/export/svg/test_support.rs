//! Helpers of the picture's unit tests: a sample's picture, and its elements found by class.

use super::{render_svg, SvgOptions};

/// The picture of a reference sample, traced with the default options.
pub(super) fn picture(name: &str) -> String {
    let (m, c, mat) = crate::testing::traced(name);
    render_svg(&m, &c, &mat, &SvgOptions::default())
}

/// True when `n` has `class` among its classes.
pub(super) fn has_class(n: &roxmltree::Node, class: &str) -> bool {
    n.attribute("class")
        .is_some_and(|c| c.split_whitespace().any(|w| w == class))
}

/// The number of `tag` elements of `class` inside `n`.
pub(super) fn count(n: roxmltree::Node, tag: &str, class: &str) -> usize {
    n.descendants()
        .filter(|d| d.has_tag_name(tag) && has_class(d, class))
        .count()
}

/// The four views (`<g class="view">`) of the picture.
pub(super) fn views<'a>(doc: &'a roxmltree::Document) -> Vec<roxmltree::Node<'a, 'a>> {
    doc.descendants()
        .filter(|n| n.has_tag_name("g") && has_class(n, "view"))
        .collect()
}
