// MCAD's spur gear test (involute_gears.scad test_gears): five gears with rims, hubs and bores.
use <MCAD/involute_gears.scad>
$fn = 48;
test_gears();
