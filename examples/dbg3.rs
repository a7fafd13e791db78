use glam::DVec3;
use truck_geometry::prelude::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let m = matrace::read_model(std::path::Path::new(&a[1])).unwrap();
    let e: usize = a[2].parse().unwrap();
    let edge = &m.edges[e];
    println!("edge {:?} range {:?}", edge.faces, edge.range);
    for f in &edge.faces { let face=&m.faces[*f]; println!("F{f} {} sign {} dom {:?}", matrace::geom::surface_kind(&face.surface), face.sign, face.domain); }
    let c = matrace::classify(&m, &Default::default());
    println!("{:?}", c.edges[e]);
    let mut hint=None; let face=&m.faces[edge.faces[1]];
    for k in 0..9 { let t = edge.range.0 + (edge.range.1-edge.range.0)*(k as f64+0.5)/9.0;
        let p = edge.curve.subs(t); let p = DVec3::new(p.x,p.y,p.z);
        let uv = matrace::geom::project_point(&face.surface, p, hint); println!("hint {hint:?} -> {uv:?}"); hint = uv; }
    for k in 0..0 {
        let t = edge.range.0 + (edge.range.1-edge.range.0)*(k as f64+0.5)/5.0;
        let p = edge.curve.subs(t); let p = DVec3::new(p.x,p.y,p.z);
        for f in &edge.faces { let face=&m.faces[*f];
            let uv = matrace::geom::project_point(&face.surface, p, None);
            if let Some(uv)=uv { let d = matrace::geom::eval_surface(&face.surface, uv.0, uv.1);
              println!("  t {t:.3} F{f} uv {uv:?} dist {:.2e} n {:?}", d.p.distance(p), d.su.cross(d.sv).normalize()*face.sign); }
        }
    }
}
#[allow(dead_code)]
fn x() {}
