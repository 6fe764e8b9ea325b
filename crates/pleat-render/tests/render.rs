//! Whole scenes rendered offscreen (on Mesa lavapipe where there is no GPU)
//! and the pictures checked against where the cloth, its shadow and its
//! strain must be. A missing adapter fails these tests: it never skips them.

use glam::{Vec2, Vec3};
use image::{AnimationDecoder, Rgba, RgbaImage};
use pleat::scene::Scene;
use pleat::Simulation;
use pleat_render::{GifWriter, Positions, RenderSettings, Renderer, Texture, View};
use std::path::Path;

fn simulation(json: &str) -> Simulation {
    scene_and_simulation(json).1
}

fn scene_and_simulation(json: &str) -> (Scene, Simulation) {
    let scene = Scene::parse(json, "test.json").unwrap();
    let sim = scene.build(Path::new("."), "test.json").unwrap();
    (scene, sim)
}

fn renderer(sim: &Simulation, settings: RenderSettings) -> Renderer {
    Renderer::headless(&sim.model, &sim.world, settings).expect(
        "rendering needs a GPU adapter; without a GPU install mesa-vulkan-drivers (lavapipe)",
    )
}

fn draw(renderer: &mut Renderer, sim: &Simulation) -> RgbaImage {
    renderer
        .render(Positions::Cpu(&sim.particles.x), &sim.world)
        .unwrap()
}

/// A horizontal 0.6 m cloth at height 0.5, weightless, over nothing.
const FLOATING_CLOTH: &str = r#"{
    "gravity": [0, 0, 0],
    "cloths": [{ "mesh": { "grid": { "resolution": [16, 16], "size": [0.6, 0.6], "center": [0, 0.5, 0] } } }]
}"#;

fn small(view: View) -> RenderSettings {
    RenderSettings {
        width: 256,
        height: 192,
        view,
        ..RenderSettings::default()
    }
}

/// Pure green on both sides, untextured: easy to tell from sky and ground.
fn green(settings: RenderSettings) -> RenderSettings {
    RenderSettings {
        texture: Some(Texture::solid([255, 255, 255, 255])),
        front_color: Some(Vec3::new(0.0, 1.0, 0.0)),
        back_color: Some(Vec3::new(0.0, 1.0, 0.0)),
        bump: Some(0.0),
        ..settings
    }
}

fn is_green(p: &Rgba<u8>) -> bool {
    let [r, g, b, _] = p.0.map(i32::from);
    g > r + 40 && g > b + 40
}

fn pixel(img: &RgbaImage, at: Vec2) -> Rgba<u8> {
    *img.get_pixel(at.x as u32, at.y as u32)
}

/// Mean luminance of the 5 x 5 pixels around `at`.
fn luminance(img: &RgbaImage, at: Vec2) -> f32 {
    let mut sum = 0.0;
    for dy in -2..=2 {
        for dx in -2..=2 {
            let p = img
                .get_pixel((at.x as i32 + dx) as u32, (at.y as i32 + dy) as u32)
                .0;
            sum += 0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32;
        }
    }
    sum / 25.0
}

#[test]
fn picture_has_the_requested_size_and_format() {
    let sim = simulation(FLOATING_CLOTH);
    let mut r = renderer(&sim, small(View::Shaded));
    let picture = draw(&mut r, &sim);
    assert_eq!(picture.dimensions(), (256, 192));
    let path = std::env::temp_dir().join(format!("pleat-render-size-{}.png", std::process::id()));
    pleat_render::save_png(&picture, &path).unwrap();
    let read = image::open(&path).unwrap();
    assert_eq!(read.color(), image::ColorType::Rgba8);
    assert_eq!((read.width(), read.height()), (256, 192));
    std::fs::remove_file(path).unwrap();
}

#[test]
fn picture_is_not_blank() {
    let sim = simulation(FLOATING_CLOTH);
    let picture = draw(&mut renderer(&sim, small(View::Shaded)), &sim);
    let colours: std::collections::HashSet<[u8; 4]> = picture.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 200, "only {} colours", colours.len());
    let lum: Vec<f32> = picture
        .pixels()
        .map(|p| p.0[..3].iter().map(|&c| c as f32).sum::<f32>() / 3.0)
        .collect();
    let mean = lum.iter().sum::<f32>() / lum.len() as f32;
    let spread = (lum.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / lum.len() as f32).sqrt();
    assert!(spread > 10.0, "luminance spread {spread}");
}

#[test]
fn cloth_pixels_are_where_its_particles_project() {
    let sim = simulation(FLOATING_CLOTH);
    let mut r = renderer(&sim, green(small(View::Shaded)));
    let picture = draw(&mut r, &sim);
    // Every particle away from the border lands on a cloth pixel.
    let cols = 16;
    let mut interior = 0;
    let mut on_cloth = 0;
    for (i, x) in sim.particles.x.iter().enumerate() {
        let (row, col) = (i / cols, i % cols);
        if row == 0 || col == 0 || row == cols - 1 || col == cols - 1 {
            continue;
        }
        interior += 1;
        on_cloth += is_green(&pixel(&picture, r.project(*x).unwrap())) as usize;
    }
    assert_eq!(on_cloth, interior, "particles on cloth pixels");
    // And the cloth's pixels fill the projected sheet, no more: its area
    // (shoelace formula over the projected corners) matches their count.
    let corners = [0, cols - 1, cols * cols - 1, cols * (cols - 1)]
        .map(|i| r.project(sim.particles.x[i]).unwrap());
    let area = (0..4)
        .map(|k| corners[k].perp_dot(corners[(k + 1) % 4]))
        .sum::<f32>()
        .abs()
        / 2.0;
    let green_pixels = picture.pixels().filter(|p| is_green(p)).count() as f32;
    assert!(
        (green_pixels / area - 1.0).abs() < 0.08,
        "{green_pixels} cloth pixels, projected area {area}"
    );
    let (lo, hi) = corners.iter().fold((Vec2::MAX, Vec2::MIN), |(lo, hi), c| {
        (lo.min(*c), hi.max(*c))
    });
    for (x, y, p) in picture.enumerate_pixels() {
        if is_green(p) {
            let at = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            assert!(
                at.cmpge(lo - 2.0).all() && at.cmple(hi + 2.0).all(),
                "cloth pixel at {at} outside {lo}..{hi}"
            );
        }
    }
}

#[test]
fn shadow_falls_on_the_ground_under_the_cloth() {
    let (scene, sim) = scene_and_simulation(
        r#"{
        "gravity": [0, 0, 0],
        "cloths": [{ "mesh": { "grid": { "resolution": [8, 8], "size": [0.5, 0.5], "center": [0, 0.6, 0] } } }],
        "colliders": [{ "shape": { "plane": { "point": [0, 0, 0], "normal": [0, 1, 0] } } }],
        "render": { "light": { "direction": [0, -1, 0] },
                    "camera": { "position": [0, 0.3, 2.0], "target": [0, 0.2, 0], "fov_degrees": 50 } }
    }"#,
    );
    let settings = RenderSettings::from_scene(scene.render.as_ref(), Path::new(".")).unwrap();
    let mut r = renderer(
        &sim,
        RenderSettings {
            width: 256,
            height: 256,
            ..settings
        },
    );
    let picture = draw(&mut r, &sim);
    // Centres of two ground checker cells of the same shade: one under the
    // cloth, one well outside its shadow.
    let under = r.project(Vec3::new(0.125, 0.0, 0.125)).unwrap();
    let beside = r.project(Vec3::new(0.625, 0.0, 0.125)).unwrap();
    assert!(!is_green(&pixel(&picture, under)));
    let (dark, lit) = (luminance(&picture, under), luminance(&picture, beside));
    assert!(
        dark < 0.75 * lit,
        "ground under the cloth {dark}, beside it {lit}"
    );

    // A window resized, the cloth moved over the other cell: the shadow follows.
    r.resize(320, 256).unwrap();
    let moved: Vec<Vec3> = sim.particles.x.iter().map(|p| *p + Vec3::X * 0.5).collect();
    let picture = r.render(Positions::Cpu(&moved), &sim.world).unwrap();
    let under = r.project(Vec3::new(0.625, 0.0, 0.125)).unwrap();
    let beside = r.project(Vec3::new(0.125, 0.0, 0.125)).unwrap();
    let (dark, lit) = (luminance(&picture, under), luminance(&picture, beside));
    assert!(
        dark < 0.75 * lit,
        "after a resize: ground under the moved cloth {dark}, where it was {lit}"
    );
}

#[test]
fn strain_view_is_red_where_stretched_and_blue_elsewhere() {
    let mut sim = simulation(FLOATING_CLOTH);
    // The top-left corner pulled 0.15 m out along the diagonal, as a pin
    // that moved away would hold it: its edges stretch about 3 times.
    sim.particles.x[0] += Vec3::new(-0.15, 0.0, -0.15);
    let mut r = renderer(&sim, small(View::Strain));
    let picture = draw(&mut r, &sim);
    let x = &sim.particles.x;
    let centroid = |t: [usize; 3]| (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
    let cols = 16;
    let stretched = pixel(&picture, r.project(centroid([0, 1, cols])).unwrap());
    let far = cols * cols - 1;
    let relaxed = pixel(
        &picture,
        r.project(centroid([far, far - 1, far - cols])).unwrap(),
    );
    let [sr, _, sb, _] = stretched.0.map(i32::from);
    let [rr, _, rb, _] = relaxed.0.map(i32::from);
    assert!(sr > 120 && sr > 2 * sb, "stretched corner {stretched:?}");
    assert!(rb > 120 && rb > 2 * rr, "relaxed corner {relaxed:?}");
}

#[test]
fn gif_has_the_requested_number_of_frames() {
    let mut sim = simulation(
        r#"{ "cloths": [{ "mesh": { "grid": { "resolution": [8, 8], "center": [0, 1, 0] } } }] }"#,
    );
    let mut r = renderer(
        &sim,
        RenderSettings {
            width: 64,
            height: 48,
            ..RenderSettings::default()
        },
    );
    let path = std::env::temp_dir().join(format!("pleat-render-anim-{}.gif", std::process::id()));
    let mut gif = GifWriter::create(&path, 1.0 / 30.0).unwrap();
    for _ in 0..3 {
        sim.step(1.0 / 30.0);
        gif.push(&draw(&mut r, &sim)).unwrap();
    }
    drop(gif);
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 3);
    assert_eq!(frames[0].buffer().dimensions(), (64, 48));
    std::fs::remove_file(path).unwrap();
}

#[test]
fn layers_of_a_flat_fold_draw_one_colour_not_stripes() {
    // The right half of the cloth folded exactly onto the left half (x to
    // -x): the two layers lie in one plane, one turned toward the camera,
    // the other away. Where front and back faces coincide the one turned
    // toward the camera is drawn, so no pixel shows the back colour.
    let mut sim = simulation(FLOATING_CLOTH);
    for x in &mut sim.particles.x {
        x.x = -x.x.abs();
    }
    let settings = RenderSettings {
        front_color: Some(Vec3::new(0.0, 1.0, 0.0)),
        back_color: Some(Vec3::new(1.0, 0.0, 0.0)),
        ..green(small(View::Shaded))
    };
    let picture = draw(&mut renderer(&sim, settings), &sim);
    let is_red = |p: &Rgba<u8>| {
        let [r, g, b, _] = p.0.map(i32::from);
        r > g + 40 && r > b + 40
    };
    let greens = picture.pixels().filter(|p| is_green(p)).count();
    let reds = picture.pixels().filter(|p| is_red(p)).count();
    assert!(greens > 1000, "{greens} front pixels");
    assert_eq!(reds, 0, "{reds} back pixels among {greens} front ones");
}

#[test]
fn paper_folded_flat_is_framed_face_on() {
    // A Miura-ori sheet squashed flat into a vertical plane facing +x: the
    // camera framing the sheet at rest would see it edge-on.
    let mut sim = simulation(
        r#"{
        "cloths": [{ "mesh": { "pattern": { "builtin": "miura-ori", "size": 0.5, "center": [0, 0.5, 0] } } }],
        "gravity": [0, 0, 0]
    }"#,
    );
    for x in &mut sim.particles.x {
        *x = Vec3::new(0.001 * x.z, 0.5 + 0.6 * (x.y - 0.5), 0.6 * x.x);
    }
    let mut r = renderer(&sim, green(small(View::Shaded)));
    assert!(r.follows_paper());
    let picture = draw(&mut r, &sim);
    let forward = (r.camera().target - r.camera().position).normalize();
    assert!(
        forward.x < -0.9,
        "looks along {forward}, not the sheet's normal"
    );
    let greens = picture.pixels().filter(|p| is_green(p)).count();
    let share = greens as f32 / (256.0 * 192.0);
    assert!(share > 0.25, "the sheet fills {share} of the picture");
    for p in &sim.particles.x {
        let at = r.project(*p).unwrap();
        assert!(
            (0.0..256.0).contains(&at.x) && (0.0..192.0).contains(&at.y),
            "{at}"
        );
    }
}

#[test]
fn positions_from_a_gpu_buffer_draw_the_same_picture() {
    use wgpu::util::DeviceExt;
    let mut sim = simulation(FLOATING_CLOTH);
    sim.particles.x[0] += Vec3::new(-0.1, 0.1, 0.0);
    let mut r = renderer(&sim, small(View::Strain));
    let from_cpu = draw(&mut r, &sim);
    // As the GPU backend keeps them: xyz and the inverse mass.
    let particles: Vec<[f32; 4]> = sim
        .particles
        .x
        .iter()
        .map(|p| [p.x, p.y, p.z, 1.0])
        .collect();
    let buffer = r
        .device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("backend positions"),
            contents: bytemuck::cast_slice(&particles),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
        });
    let from_gpu = r.render(Positions::Gpu(&buffer), &sim.world).unwrap();
    assert!(from_cpu == from_gpu, "the two pictures differ");
    // A buffer too small for the model is refused.
    let short = r.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    assert!(r.render(Positions::Gpu(&short), &sim.world).is_err());
    // So is one the shaders cannot read.
    let unreadable = r.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: buffer.size(),
        usage: wgpu::BufferUsages::VERTEX,
        mapped_at_creation: false,
    });
    let err = r
        .render(Positions::Gpu(&unreadable), &sim.world)
        .unwrap_err();
    assert!(err.to_string().contains("STORAGE"), "{err}");
}

#[test]
fn every_view_draws_paper_and_colliders() {
    let sim = simulation(
        r#"{
        "cloths": [{ "mesh": { "pattern": { "builtin": "miura-ori", "size": 0.5, "center": [0, 0.5, 0] } } }],
        "colliders": [
            { "shape": { "sphere": { "center": [0.5, 0.2, 0], "radius": 0.15 } } },
            { "shape": { "box": { "center": [-0.5, 0.2, 0], "half_extents": [0.1, 0.1, 0.1] } } },
            { "shape": { "capsule": { "a": [0, 0.1, 0.4], "b": [0.3, 0.1, 0.4], "radius": 0.05 } } },
            { "shape": { "icosphere": { "center": [0, 0.2, -0.4], "radius": 0.1, "subdivisions": 2 } } }
        ],
        "gravity": [0, 0, 0]
    }"#,
    );
    let mut pictures = Vec::new();
    for (_, view) in View::ALL {
        let mut r = renderer(
            &sim,
            RenderSettings {
                width: 96,
                height: 64,
                view,
                mirror_colliders: view == View::Shaded,
                ..RenderSettings::default()
            },
        );
        pictures.push(draw(&mut r, &sim));
    }
    for i in 0..pictures.len() {
        for j in i + 1..pictures.len() {
            assert!(
                pictures[i] != pictures[j],
                "views {i} and {j} look the same"
            );
        }
    }
}

#[test]
fn bad_sizes_and_particle_counts_are_errors() {
    let sim = simulation(FLOATING_CLOTH);
    let err = Renderer::headless(
        &sim.model,
        &sim.world,
        RenderSettings {
            width: 0,
            ..RenderSettings::default()
        },
    )
    .err()
    .expect("a zero width is refused");
    assert!(err.to_string().contains("out of range"), "{err}");
    let mut r = renderer(&sim, small(View::Shaded));
    assert!(r.render(Positions::Cpu(&[Vec3::ZERO]), &sim.world).is_err());
}

#[test]
fn a_texture_named_in_the_scene_is_drawn() {
    let dir = std::env::temp_dir().join(format!("pleat-render-texture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    RgbaImage::from_pixel(4, 4, Rgba([20, 40, 255, 255]))
        .save(dir.join("blue.png"))
        .unwrap();
    let scene = Scene::parse(
        r#"{ "gravity": [0, 0, 0],
             "cloths": [{ "mesh": { "grid": { "resolution": [8, 8], "center": [0, 0.5, 0] } } }],
             "render": { "texture": "blue.png", "front_color": [1, 1, 1], "back_color": [1, 1, 1], "bump": 0 } }"#,
        "t.json",
    )
    .unwrap();
    let sim = scene.build(&dir, "t.json").unwrap();
    let settings = RenderSettings::from_scene(scene.render.as_ref(), &dir).unwrap();
    let mut r = renderer(
        &sim,
        RenderSettings {
            width: 128,
            height: 96,
            ..settings
        },
    );
    let picture = draw(&mut r, &sim);
    let [red, _, blue, _] = pixel(&picture, r.project(Vec3::new(0.0, 0.5, 0.0)).unwrap()).0;
    assert!(
        blue > 150 && red < 80,
        "cloth centre {red} red, {blue} blue"
    );
    // A texture that is not there is an error that names it.
    let missing = Scene::parse(
        r#"{ "cloths": [{ "mesh": { "grid": { "resolution": [2, 2] } } }], "render": { "texture": "none.png" } }"#,
        "t.json",
    )
    .unwrap();
    let err = RenderSettings::from_scene(missing.render.as_ref(), &dir).unwrap_err();
    assert!(err.to_string().contains("none.png"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn displacement_and_bump_change_the_surface() {
    let sim = simulation(FLOATING_CLOTH);
    let picture = |bump: f32, displacement: f32| {
        let settings = RenderSettings {
            bump: Some(bump),
            displacement,
            ..small(View::Shaded)
        };
        draw(&mut renderer(&sim, settings), &sim)
    };
    let flat = picture(0.0, 0.0);
    assert!(picture(0.0015, 0.0) != flat, "bump mapping changed nothing");
    assert!(picture(0.0, 0.05) != flat, "displacement changed nothing");
}
