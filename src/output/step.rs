//! Writing the seams and junctions as a STEP AP214 wireframe.
