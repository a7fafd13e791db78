//! [`Element`]: a face, an edge or a vertex of the model, by index.
//!
//! The tracer touches elements (the paper's "boundary segments": faces, reflex edges, reflex
//! vertices), distance queries find the element a nearest point lies on, and sheets are
//! named by the elements their balls touch. Reports write an element as `F3`, `E7` or `V2`.

use std::fmt;

/// A face, an edge or a vertex of the model (indices into `Model::faces`, `edges`,
/// `vertices`). Ordered faces first, then edges, then vertices, each by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Element {
    Face(usize),
    Edge(usize),
    Vertex(usize),
}

impl Element {
    /// The vertices the element reaches: a vertex itself, an edge's two ends, a face's
    /// loops' (their edges' ends, and a vertex loop's vertex: a cone's apex). Elements past
    /// the model's ends reach none.
    pub fn vertices(self, model: &super::Model) -> Vec<usize> {
        match self {
            Element::Vertex(v) => vec![v],
            Element::Edge(g) => model.edges.get(g).map_or(vec![], |e| e.vertices.to_vec()),
            Element::Face(f) => model.faces.get(f).map_or(vec![], |face| {
                face.loops
                    .iter()
                    .flat_map(|l| {
                        l.edges
                            .iter()
                            .filter_map(|oe| model.edges.get(oe.edge))
                            .flat_map(|e| e.vertices)
                            .chain(l.vertex)
                    })
                    .collect()
            }),
        }
    }

    /// The faces the element lies on: a face itself, an edge's, a vertex's (those of its
    /// edges, and of a vertex loop at it), sorted, without repeats.
    pub fn faces(self, model: &super::Model) -> Vec<usize> {
        let mut out: Vec<usize> = match self {
            Element::Face(f) => vec![f],
            Element::Edge(g) => model.edges.get(g).map_or(vec![], |e| e.faces.clone()),
            Element::Vertex(v) => model
                .edges
                .iter()
                .filter(|e| e.vertices.contains(&v))
                .flat_map(|e| e.faces.iter().copied())
                .chain(
                    (0..model.faces.len())
                        .filter(|&f| model.faces[f].loops.iter().any(|l| l.vertex == Some(v))),
                )
                .collect(),
        };
        out.sort_unstable();
        out.dedup();
        out
    }
}

impl fmt::Display for Element {
    /// `F3`, `E7`, `V2`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Element::Face(i) => write!(f, "F{i}"),
            Element::Edge(i) => write!(f, "E{i}"),
            Element::Vertex(i) => write!(f, "V{i}"),
        }
    }
}

impl serde::Serialize for Element {
    /// As its [`Display`](fmt::Display) form, `"F3"`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for Element {
    /// From its text, `"F3"`.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Element, D::Error> {
        let text = <String as serde::Deserialize>::deserialize(d)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

impl std::str::FromStr for Element {
    type Err = String;

    /// Reads `F3`, `E7`, `V2`.
    fn from_str(s: &str) -> Result<Element, String> {
        let index = |rest: &str| {
            rest.parse::<usize>()
                .ok()
                .filter(|_| rest.bytes().all(|b| b.is_ascii_digit()))
        };
        let parsed = match (s.as_bytes().first(), s.get(1..)) {
            (Some(b'F'), Some(rest)) => index(rest).map(Element::Face),
            (Some(b'E'), Some(rest)) => index(rest).map(Element::Edge),
            (Some(b'V'), Some(rest)) => index(rest).map(Element::Vertex),
            _ => None,
        };
        parsed.ok_or_else(|| format!("not an element id (F3, E7, V2): {s:?}"))
    }
}

#[cfg(test)]
mod tests {
    use super::Element;

    #[test]
    fn ids_print_parse_and_serialise_alike() {
        for (e, id) in [
            (Element::Face(3), "F3"),
            (Element::Edge(17), "E17"),
            (Element::Vertex(0), "V0"),
        ] {
            assert_eq!(e.to_string(), id);
            assert_eq!(id.parse::<Element>(), Ok(e));
            assert_eq!(serde_json::to_string(&e).unwrap(), format!("\"{id}\""));
        }
        for bad in ["", "F", "X3", "F-1", "F+1", "F 3", "E3x", "f3"] {
            assert!(bad.parse::<Element>().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn faces_order_before_edges_before_vertices() {
        let mut v = vec![
            Element::Vertex(0),
            Element::Edge(5),
            Element::Face(9),
            Element::Face(1),
        ];
        v.sort();
        assert_eq!(
            v,
            [
                Element::Face(1),
                Element::Face(9),
                Element::Edge(5),
                Element::Vertex(0)
            ]
        );
    }
}
