// Two boxes sharing the plane z = 0.05: "fem" below, "dem" above, 0.1 m x 0.1 m each.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.1, 0.05};
Box(2) = {0, 0, 0.05, 0.1, 0.1, 0.05};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
MeshSize{:} = 0.02;
Physical Volume("fem") = {1};
Physical Volume("dem") = {2};
