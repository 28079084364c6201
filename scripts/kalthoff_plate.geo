// Kalthoff plate 0.1 x 0.2 m, unstructured triangles (particles at their centroids);
// the notch lines are embedded so that no centroid lies on them.
If (!Exists(lc)) lc = 0.00152; EndIf
Point(1) = {0, -0.1, 0, lc}; Point(2) = {0.1, -0.1, 0, lc};
Point(3) = {0.1, 0.1, 0, lc}; Point(4) = {0, 0.1, 0, lc};
Point(5) = {0, 0.025, 0, lc}; Point(6) = {0.05, 0.025, 0, lc};
Point(7) = {0, -0.025, 0, lc}; Point(8) = {0.05, -0.025, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 7}; Line(6) = {7, 1};
Line(7) = {5, 6}; Line(8) = {7, 8};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Line {7, 8} In Surface {1};
Physical Surface("plate") = {1};
Mesh.Algorithm = 6;
