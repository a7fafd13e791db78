use glam::DVec3;
use truck_geometry::prelude::*;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&a[1]).unwrap();
    let id: u64 = a[2].parse().unwrap();
    let p = DVec3::new(a[3].parse().unwrap(), a[4].parse().unwrap(), a[5].parse().unwrap());
    let table = truck_stepio::r#in::Table::from_step(&text).unwrap();
    use truck_stepio::r#in::ruststep::tables::{IntoOwned, PlaceHolder};
    use truck_stepio::r#in::ruststep::ast::Name;
    let any = PlaceHolder::<truck_stepio::r#in::SurfaceAnyHolder>::Ref(Name::Entity(id)).into_owned(&table).unwrap();
    let s = matrace::brep::model::Surface::try_from(&any).unwrap();
    println!("range {:?}", s.parameter_range());
    for (u,v) in [(0.0,0.0),(0.3,0.5),(0.7,0.2),(1.0,1.0)] {
      let d = matrace::geom::eval_surface(&s, u, v);
      println!("{u} {v} ours {:?} truck {:?}", d.p, s.subs(u,v));
    }
    let r = matrace::geom::project_point(&s, p, None);
    println!("{:?} {:?}", r, r.map(|r| s.subs(r.0,r.1)));
    let mut best=(1e9,0.0,0.0);
    for i in 0..=20000 { for j in 0..=20 { let u=57.260386184106*i as f64/20000.0; let v=j as f64/20.0; let q=s.subs(u,v); let d=((q.x-p.x).powi(2)+(q.y-p.y).powi(2)+(q.z-p.z).powi(2)).sqrt(); if d<best.0 {best=(d,u,v);} } }
    println!("brute {:?}", best);
    println!("truck {:?}", s.search_nearest_parameter(Point3::new(p.x,p.y,p.z), None, 100));
}
#[allow(dead_code)]
fn brute() {}
