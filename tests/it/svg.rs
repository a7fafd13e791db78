//! `trace` writes the picture `<stem>.mat.svg` beside the report.

use crate::common::{matrace, root, sample};

fn has_class(n: &roxmltree::Node, class: &str) -> bool {
    n.attribute("class")
        .is_some_and(|c| c.split_whitespace().any(|w| w == class))
}

#[test]
fn trace_writes_a_picture_with_every_seam_and_junction_in_four_views() {
    let dir = tempfile::tempdir().unwrap();
    let out = matrace(
        &[
            "trace",
            sample("box.step").to_str().unwrap(),
            "-o",
            dir.path().to_str().unwrap(),
        ],
        &root(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("box.mat.json").is_file());
    let path = dir.path().join("box.mat.svg");
    let text = std::fs::read_to_string(&path).expect("box.mat.svg written");
    let doc = roxmltree::Document::parse(&text).expect("box.mat.svg is well-formed XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let views: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("g") && has_class(n, "view"))
        .collect();
    assert_eq!(views.len(), 4);
    for v in &views {
        let seams = v
            .descendants()
            .filter(|n| n.has_tag_name("g") && has_class(n, "seam"))
            .count();
        let junctions = v
            .descendants()
            .filter(|n| n.has_tag_name("circle") && has_class(n, "junction"))
            .count();
        assert_eq!((seams, junctions), (12, 4), "{:?}", v.attribute("id"));
    }
    assert!(doc.descendants().any(|n| has_class(&n, "colour-bar")));
    assert!(text.contains("box.step"));
    // The outputs, and no temporary file left behind.
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert!(names.contains(&"box.mat.json".to_string()), "{names:?}");
    assert!(names.contains(&"box.mat.svg".to_string()), "{names:?}");
    assert!(
        names
            .iter()
            .all(|n| !n.starts_with('.') && !n.ends_with(".tmp")),
        "temporary file left behind: {names:?}"
    );
    // The same input gives the same picture, byte for byte.
    let again = tempfile::tempdir().unwrap();
    let out = matrace(
        &[
            "trace",
            sample("box.step").to_str().unwrap(),
            "-o",
            again.path().to_str().unwrap(),
        ],
        &root(),
    );
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(again.path().join("box.mat.svg")).unwrap(),
        text.as_bytes()
    );
}
