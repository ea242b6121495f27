// MCAD's meshing double-helix gears (involute_gears.scad test_meshing_double_helix): twisted
// extrusions, long thin triangles along the teeth.
use <MCAD/involute_gears.scad>
$fn = 48;
test_meshing_double_helix();
