use clod_viewer::clod::{self, ClodOptions, SimplificationPose};
use clod_viewer::metrics::{bounds_diagonal, surface_distance};
fn main() {
    let f = std::env::args().nth(1).unwrap();
    let c = clod_viewer::import::from_glb(&std::fs::read(&f).unwrap()).unwrap();
    let n = c.mesh.triangle_count();
    let counts = vec![n / 2, n / 4, n / 10, n / 20, n / 100];
    let diag = bounds_diagonal(&c.mesh.positions);
    let clip0 = c.clips[0].clone();
    for pose in [
        SimplificationPose::Bind,
        SimplificationPose::MultiPose { frames_per_clip: 8 },
        SimplificationPose::ClipFrame { clip: clip0.name.clone(), time: clip0.duration() / 2.0 },
    ] {
        let o =
            ClodOptions { level_triangles: Some(counts.clone()), pose: pose.clone(), ..Default::default() };
        let b = clod::build(&c, &o, &mut |_| {}).unwrap();
        let mut s = String::new();
        for i in 0..b.levels.len() {
            let d = surface_distance(
                (&c.mesh.positions, &c.mesh.indices),
                (&b.level_bind_positions(i), &b.levels[i].indices),
                10000,
                12345,
            )
            .unwrap();
            s += &format!(" {:.3}", 100.0 * d.mean / diag);
        }
        // animated
        let (mut sum, mut k) = (0.0, 0);
        for clip in &c.clips {
            for fr in 0..4 {
                let t = clip.duration() * (fr as f32 + 0.5) / 4.0;
                let pose = c.pose_at(clip, t);
                let skin = c.skin_matrices(&pose);
                let full = c.skinned_positions(&pose);
                for i in 0..b.levels.len() {
                    let d = surface_distance(
                        (&full, &c.mesh.indices),
                        (&b.level_skinned_positions(i, &skin), &b.levels[i].indices),
                        2500,
                        12345,
                    )
                    .unwrap();
                    sum += d.mean / diag * 100.0;
                    k += 1;
                }
            }
        }
        println!("{:?}: bind mean%{s} | animated mean% {:.4}", pose, sum / k as f32);
    }
}
