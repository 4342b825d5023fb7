// A box as a triangle mesh, for the tests that write mesh files
// (`tests/meshes.rs`, `tests/published_shapes.rs`), which `include!` it.

/// The corners of the box of half-extents `half`: corner `i` has `+half[k]`
/// where bit `k` of `i` is set, `-half[k]` where it is not.
fn cube_corners(half: [f64; 3]) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 0 { -half[k] } else { half[k] }))
        .collect()
}

/// The box's twelve outward triangles, by corner.
const CUBE_FACES: [[usize; 3]; 12] = [
    [0, 2, 3],
    [0, 3, 1],
    [4, 5, 7],
    [4, 7, 6],
    [0, 1, 5],
    [0, 5, 4],
    [2, 6, 7],
    [2, 7, 3],
    [0, 4, 6],
    [0, 6, 2],
    [1, 3, 7],
    [1, 7, 5],
];
