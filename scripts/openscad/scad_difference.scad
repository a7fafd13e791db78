// scad_difference: cube minus a through cylinder.
// Block [0,40]x[0,40]x[0,20] with a vertical through hole r=10 on the axis x=y=20.
// Default $fn/$fa/$fs on purpose: FreeCAD's importCSG then makes an exact cylinder
// (small $fn would give a polygonal prism).
difference() {
    cube([40, 40, 20]);
    translate([20, 20, -5]) cylinder(r = 10, h = 30);
}
