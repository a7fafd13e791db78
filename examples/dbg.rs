fn main() {
    matrace::panic_guard::install_quiet_hook();
    for a in std::env::args().skip(1) {
        let t = std::time::Instant::now();
        match matrace::read_model(std::path::Path::new(&a)) {
            Ok(m) => {
                let vl: usize = m.faces.iter().map(|f| f.loops.iter().filter(|l| l.vertex.is_some()).count()).sum();
                println!("{a}: solids {} shells {} faces {} edges {} vertices {} vloops {vl} unit {} {:.1}ms", m.solids.len(), m.shells.len(), m.faces.len(), m.edges.len(), m.vertices.len(), m.source.file_unit, t.elapsed().as_secs_f64()*1e3);
                if std::env::var("V").is_ok() { for (i,f) in m.faces.iter().enumerate() { println!("  F{i} #{} sign {} outer {:?} dom {:?}", f.step_id, f.sign, f.outer, f.domain); } }
            }
            Err(e) => println!("{a}: ERROR {e}"),
        }
    }
}
