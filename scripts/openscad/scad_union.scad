// scad_union: union of primitives, a cube with a hemispherical dome.
// Block [0,40]x[0,40]x[0,20] and a sphere r=10 centred on the top face at (20,20,20):
// the lower half of the sphere is inside the block, the upper half is a dome.
union() {
    cube([40, 40, 20]);
    translate([20, 20, 20]) sphere(r = 10);
}
