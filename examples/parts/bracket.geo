// An L-shaped bracket with a bolt hole, drawn in millimetres with Gmsh's OpenCASCADE
// kernel: the CAD part of examples/stl_bracket.yaml. Its surface, as a CAD program
// would export it (binary STL):
//   gmsh examples/parts/bracket.geo -2 -o examples/parts/bracket.stl
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 40, 20, 4};           // the base, 40 x 20 x 4
Box(2) = {0, 0, 0, 4, 20, 30};           // the upright, 30 high
Cylinder(3) = {25, 10, -1, 0, 0, 6, 4};  // the bolt hole, radius 4
BooleanUnion(4) = {Volume{1}; Delete;}{Volume{2}; Delete;};
BooleanDifference(5) = {Volume{4}; Delete;}{Volume{3}; Delete;};
Mesh.MeshSizeMax = 3;
Mesh.Binary = 1;
