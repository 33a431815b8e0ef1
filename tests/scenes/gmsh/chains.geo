// Test input for tests/test_gmsh.cpp (GmshChains): small groups of straight lines whose node
// positions are known by hand.

// rod_reversed: A (0,0,0) -> X (1,0,0) <- B (3,0,0); the second line is drawn backwards.
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {3, 0, 0};
Line(1) = {1, 2};
Line(2) = {3, 2};
Physical Curve("rod_reversed") = {1, 2};
Physical Point("A") = {1};
Physical Point("B") = {3};

// rod_unnamed: (0,1,0) -> (1,1,0) -> (3,1,0), no named points, curves listed last-first.
Point(11) = {0, 1, 0};
Point(12) = {1, 1, 0};
Point(13) = {3, 1, 0};
Line(11) = {11, 12};
Line(12) = {12, 13};
Physical Curve("rod_unnamed") = {12, 11};

// rod_short: C (0,2,0) -> (0.1,2,0) -> D (10.1,2,0): the short curve still gets a segment.
Point(21) = {0, 2, 0};
Point(22) = {0.1, 2, 0};
Point(23) = {10.1, 2, 0};
Line(21) = {21, 22};
Line(22) = {22, 23};
Physical Curve("rod_short") = {21, 22};
Physical Point("C") = {21};
Physical Point("D") = {23};
