//! The medial sheets' triangle mesh as Wavefront OBJ text (`<stem>.sheets.obj`).
//!
//! One group per sheet (`g sheet_<id>`, or `g unbounded_<groups>` for a sheet whose boundary
//! did not close), vertices in millimetres with six decimals, faces numbered from 1. The
//! radius of each vertex's ball has no place in OBJ and is left out.

use crate::medial::SheetMesh;
use std::fmt::Write as _;

/// The mesh as Wavefront OBJ text, with `title` (the part) in the header comment.
pub fn sheet_mesh_obj(mesh: &SheetMesh, title: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# matrace medial sheets of {title}");
    let _ = writeln!(
        s,
        "# {} vertices, {} triangles, {} sheets",
        mesh.vertices.len(),
        mesh.triangles(),
        mesh.parts.len()
    );
    for v in &mesh.vertices {
        let _ = writeln!(s, "v {:.6} {:.6} {:.6}", v[0], v[1], v[2]);
    }
    for p in &mesh.parts {
        match p.sheet {
            Some(id) => {
                let _ = writeln!(s, "g sheet_{id}");
            }
            None => {
                let _ = writeln!(s, "g unbounded_{}", p.name.replace('|', "_"));
            }
        }
        for t in &p.triangles {
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Boundary;
    use crate::medial::sheet_mesh::MeshPart;
    use crate::medial::{MeshOptions, TraceOptions};

    #[test]
    fn obj_text_lists_vertices_then_groups_of_faces_numbered_from_one() {
        let mesh = SheetMesh {
            vertices: vec![
                [0.0, 0.0, 0.0, 1.0],
                [1.0, 0.0, 0.0, 1.0],
                [0.0, 1.5, -0.25, 2.0],
                [1.0, 1.0, 1.0, 0.5],
            ],
            parts: vec![
                MeshPart {
                    sheet: Some(3),
                    name: "G0|G1".into(),
                    triangles: vec![[0, 1, 2]],
                },
                MeshPart {
                    sheet: None,
                    name: "G2|G5".into(),
                    triangles: vec![[1, 3, 2], [0, 3, 1]],
                },
            ],
        };
        assert_eq!(
            sheet_mesh_obj(&mesh, "part.step"),
            "# matrace medial sheets of part.step\n\
             # 4 vertices, 3 triangles, 2 sheets\n\
             v 0.000000 0.000000 0.000000\n\
             v 1.000000 0.000000 0.000000\n\
             v 0.000000 1.500000 -0.250000\n\
             v 1.000000 1.000000 1.000000\n\
             g sheet_3\n\
             f 1 2 3\n\
             g unbounded_G2_G5\n\
             f 2 4 3\n\
             f 1 4 2\n"
        );
    }

    /// Box [0,60]×[0,40]×[0,20]: every vertex and triangle of its mesh, one group per sheet.
    #[test]
    fn box_mesh_has_every_vertex_and_triangle_and_a_group_per_sheet() {
        let (m, c) = crate::testing::classified("box.step");
        let opts = TraceOptions::for_model(&m);
        let b = Boundary::new(&m);
        let mat = crate::medial::trace_with_boundary(&m, &b, &c, &opts);
        let s = crate::medial::sheets(&m, &c, &mat);
        let mesh = crate::medial::sheet_mesh(&m, &b, &c, &s, &MeshOptions::new(opts.accuracy));
        let obj = sheet_mesh_obj(&mesh, "box");
        assert_eq!(
            obj.lines().filter(|l| l.starts_with("v ")).count(),
            mesh.vertices.len()
        );
        assert_eq!(
            obj.lines().filter(|l| l.starts_with("f ")).count(),
            mesh.triangles()
        );
        assert_eq!(
            obj.lines().filter(|l| l.starts_with("g sheet_")).count(),
            13
        );
    }
}
