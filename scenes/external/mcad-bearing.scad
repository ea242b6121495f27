// MCAD's bearing test (bearing.scad test_bearing): skate bearings with their balls' races.
include <MCAD/bearing.scad>
$fn = 48;
test_bearing();
