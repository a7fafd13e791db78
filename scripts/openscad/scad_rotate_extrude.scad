// scad_rotate_extrude: rotate_extrude of an offset rectangle -> a ring (washer).
// Rectangle x in [15,25], y in [0,8] revolved about the z axis: inner radius 15,
// outer radius 25, height 8 (z in [0,8]).
rotate_extrude() translate([15, 0]) square([10, 8]);
