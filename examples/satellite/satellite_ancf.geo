// Four-panel satellite with ANCF panel beams and springs (examples/satellite/satellite_ancf.yaml),
// units m. The geometry of satellite.geo, with the joints between two ANCF chains split:
// an ANCF node carries one slope, so two chains sharing a node would be welded there. The
// paper's joints are pins, so each second chain gets its own end point at the same place
// (A1b..A4b: the second panel beam at each cube corner; P1s..P4s: the spring's end on its
// panel beam), joined again by the scene (attached points of the cube, spherical joints).
// Read by flexsens::meshCurves (meshes/GmshCurves.hpp): only the named Physical Curves and
// Physical Points matter; segment counts are set by the caller, not here.
//
// Cube x in [0,2], y in [0,2], z in [-2,0]; top face z = 0 with corners A1..A4; panels stand
// folded up (z from 0 to 10). B1/B5, B2/B6, B3/B7 and B4/B8 coincide in space but are
// DISTINCT points (each panel has its own end); nothing may merge them, hence no Coherence
// and no automatic coherence.
Geometry.AutoCoherence = 0;

r = Sqrt(2) / 2;  // sin(135 deg) = -cos(135 deg)

// --- points ------------------------------------------------------------------------------
Point(1) = {0, 0, 0};   // A1
Point(2) = {0, 2, 0};   // A2
Point(3) = {2, 0, 0};   // A3
Point(4) = {2, 2, 0};   // A4
Point(11) = {0, 0, 10}; // B1
Point(12) = {0, 2, 10}; // B2
Point(13) = {2, 0, 10}; // B3
Point(14) = {2, 2, 10}; // B4
Point(15) = {0, 0, 10}; // B5 (same place as B1)
Point(16) = {0, 2, 10}; // B6 (same place as B2)
Point(17) = {2, 0, 10}; // B7 (same place as B3)
Point(18) = {2, 2, 10}; // B8 (same place as B4)
Point(21) = {0, 0, -2}; // C1, bottom corner of the cube
Point(5) = {0, 0, 0};   // A1b: start of panel beam A1-B5 (same place as A1)
Point(6) = {0, 2, 0};   // A2b: start of panel beam A2-B6
Point(7) = {2, 0, 0};   // A3b: start of panel beam A3-B7
Point(8) = {2, 2, 0};   // A4b: start of panel beam A4-B8

// Springs: S on the top face, P 1 m along a panel beam, arc centre, and the arc's mid point
// (135 deg from S); each spring is the 270-degree arc S -> mid -> P of radius 1.
Point(31) = {1, 0, 0};  // S1 (plane y = 0)
Point(32) = {1, 2, 0};  // S2 (plane y = 2)
Point(33) = {2, 1, 0};  // S3 (plane x = 2)
Point(34) = {0, 1, 0};  // S4 (plane x = 0)
Point(41) = {0, 0, 1};  // P1 on panel A1-B1
Point(42) = {2, 2, 1};  // P2 on panel A4-B4
Point(43) = {2, 0, 1};  // P3 on panel A3-B7
Point(44) = {0, 2, 1};  // P4 on panel A2-B6
Point(71) = {0, 0, 1};  // P1s: end of spring 1 (same place as P1)
Point(72) = {2, 2, 1};  // P2s
Point(73) = {2, 0, 1};  // P3s
Point(74) = {0, 2, 1};  // P4s
Point(51) = {1, 0, 1};  // centre of spring 1
Point(52) = {1, 2, 1};  // centre of spring 2
Point(53) = {2, 1, 1};  // centre of spring 3
Point(54) = {0, 1, 1};  // centre of spring 4
// Angle t measured from S about the centre: spring 1 at t = 90 deg is (2,0,1), 180 deg
// (1,0,2), 270 deg P1 = (0,0,1); mid points at t = 135 deg.
Point(61) = {1 + r, 0, 1 + r};  // spring 1 mid (side x > 1)
Point(62) = {1 - r, 2, 1 + r};  // spring 2 mid (side x < 1, arc through (0,2,1))
Point(63) = {2, 1 + r, 1 + r};  // spring 3 mid (side y > 1, arc through (2,2,1))
Point(64) = {0, 1 - r, 1 + r};  // spring 4 mid (side y < 1, arc through (0,0,1))

// --- panel beams (A -> B; those carrying a spring are split at P) -----------------------
Line(101) = {1, 41};   Line(102) = {41, 11};  // A1 -> P1 -> B1
Line(103) = {2, 12};                          // A2 -> B2
Line(104) = {3, 13};                          // A3 -> B3
Line(105) = {4, 42};   Line(106) = {42, 14};  // A4 -> P2 -> B4
Line(107) = {5, 15};                          // A1 -> B5
Line(108) = {7, 43};   Line(109) = {43, 17};  // A3 -> P3 -> B7
Line(110) = {6, 44};   Line(111) = {44, 16};  // A2 -> P4 -> B6
Line(112) = {8, 18};                          // A4 -> B8

// --- rigid bars and diagonals ------------------------------------------------------------
Line(121) = {11, 12};  // B1 -> B2
Line(122) = {13, 14};  // B3 -> B4
Line(123) = {15, 17};  // B5 -> B7
Line(124) = {16, 18};  // B6 -> B8
Line(131) = {1, 12};   // A1 -> B2
Line(132) = {2, 18};   // A2 -> B8
Line(133) = {4, 13};   // A4 -> B3
Line(134) = {3, 15};   // A3 -> B5

// --- springs: two 135-degree Circle arcs each (a Circle must be shorter than 180 deg) ----
Circle(141) = {31, 51, 61};  Circle(142) = {61, 51, 71};  // S1 -> P1
Circle(143) = {32, 52, 62};  Circle(144) = {62, 52, 72};  // S2 -> P2
Circle(145) = {33, 53, 63};  Circle(146) = {63, 53, 73};  // S3 -> P3
Circle(147) = {34, 54, 64};  Circle(148) = {64, 54, 74};  // S4 -> P4

// --- physical groups ---------------------------------------------------------------------
Physical Curve("panel_A1B1") = {101, 102};
Physical Curve("panel_A2B2") = {103};
Physical Curve("panel_A3B3") = {104};
Physical Curve("panel_A4B4") = {105, 106};
Physical Curve("panel_A1B5") = {107};
Physical Curve("panel_A3B7") = {108, 109};
Physical Curve("panel_A2B6") = {110, 111};
Physical Curve("panel_A4B8") = {112};
Physical Curve("bar_B1B2") = {121};
Physical Curve("bar_B3B4") = {122};
Physical Curve("bar_B5B7") = {123};
Physical Curve("bar_B6B8") = {124};
Physical Curve("diag_A1B2") = {131};
Physical Curve("diag_A2B8") = {132};
Physical Curve("diag_A4B3") = {133};
Physical Curve("diag_A3B5") = {134};
Physical Curve("spring1") = {141, 142};
Physical Curve("spring2") = {143, 144};
Physical Curve("spring3") = {145, 146};
Physical Curve("spring4") = {147, 148};

Physical Point("A1") = {1};
Physical Point("A2") = {2};
Physical Point("A3") = {3};
Physical Point("A4") = {4};
Physical Point("B1") = {11};
Physical Point("B2") = {12};
Physical Point("B3") = {13};
Physical Point("B4") = {14};
Physical Point("B5") = {15};
Physical Point("B6") = {16};
Physical Point("B7") = {17};
Physical Point("B8") = {18};
Physical Point("C1") = {21};
Physical Point("S1") = {31};
Physical Point("S2") = {32};
Physical Point("S3") = {33};
Physical Point("S4") = {34};
Physical Point("P1") = {41};
Physical Point("P2") = {42};
Physical Point("P3") = {43};
Physical Point("P4") = {44};
Physical Point("A1b") = {5};
Physical Point("A2b") = {6};
Physical Point("A3b") = {7};
Physical Point("A4b") = {8};
Physical Point("P1s") = {71};
Physical Point("P2s") = {72};
Physical Point("P3s") = {73};
Physical Point("P4s") = {74};
