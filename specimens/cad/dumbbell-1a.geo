// A dumb-bell after ISO 527-2 type 1A, drawn for Gmsh (OpenCASCADE kernel), mm:
// overall length 170, parallel length 80 (narrow width 10), end width 20, thickness 4, one fillet
// arc of radius 24 tangent to the narrow section (it meets the 20 mm tab at x = ±54.66, the
// 1A drawing's 24/60 mm compound radius simplified), 25 mm grip tabs at each end.
// Physical groups: "grip_left", "grip_right" (top and bottom faces of the tabs), "specimen" (volume).
SetFactory("OpenCASCADE");
L = 170; Lp = 80; W = 10; We = 20; R = 24; T = 4; G = 25;
a = Lp / 2;  h = W / 2;  H = We / 2;  c = h + R;
x1 = a + Sqrt(R^2 - (c - H)^2);       // where the fillet arc meets the tab width
e = L / 2;  g = e - G;
// outline, counter-clockwise from the bottom-left corner
Point(1) = {-e, -H, 0};  Point(2) = {-g, -H, 0};  Point(3) = {-x1, -H, 0};
Point(4) = {-a, -h, 0};  Point(5) = {a, -h, 0};   Point(6) = {x1, -H, 0};
Point(7) = {g, -H, 0};   Point(8) = {e, -H, 0};   Point(9) = {e, H, 0};
Point(10) = {g, H, 0};   Point(11) = {x1, H, 0};  Point(12) = {a, h, 0};
Point(13) = {-a, h, 0};  Point(14) = {-x1, H, 0}; Point(15) = {-g, H, 0};
Point(16) = {-e, H, 0};
Point(21) = {-a, -c, 0}; Point(22) = {a, -c, 0};  Point(23) = {a, c, 0};  Point(24) = {-a, c, 0};  // arc centres
Line(1) = {1, 2};  Line(2) = {2, 3};  Circle(3) = {3, 21, 4};  Line(4) = {4, 5};  Circle(5) = {5, 22, 6};
Line(6) = {6, 7};  Line(7) = {7, 8};  Line(8) = {8, 9};  Line(9) = {9, 10};  Line(10) = {10, 11};
Circle(11) = {11, 23, 12};  Line(12) = {12, 13};  Circle(13) = {13, 24, 14};  Line(14) = {14, 15};
Line(15) = {15, 16};  Line(16) = {16, 1};
Line(17) = {2, 15};  Line(18) = {7, 10};  // the grip tabs' inner edges
Curve Loop(1) = {1, 17, 15, 16};                                // left tab
Curve Loop(2) = {2, 3, 4, 5, 6, 18, 10, 11, 12, 13, 14, -17};   // between the grips
Curve Loop(3) = {7, 8, 9, -18};                                 // right tab
Plane Surface(1) = {1};  Plane Surface(2) = {2};  Plane Surface(3) = {3};
Extrude {0, 0, T} { Surface{1, 2, 3}; }
Coherence;
d = 1e-3;
Physical Surface("grip_left") = Surface In BoundingBox{-e - d, -H - d, -d, -g + d, H + d, d};
Physical Surface("grip_left") += Surface In BoundingBox{-e - d, -H - d, T - d, -g + d, H + d, T + d};
Physical Surface("grip_right") = Surface In BoundingBox{g - d, -H - d, -d, e + d, H + d, d};
Physical Surface("grip_right") += Surface In BoundingBox{g - d, -H - d, T - d, e + d, H + d, T + d};
Physical Volume("specimen") = Volume{:};
