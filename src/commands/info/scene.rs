//! `dynray info FILE`: one-line summaries of a scene's normals and animation.

use super::super::thousands;
use dynray_scene::{NormalSource, Scene};

/// Where the rendered normals come from, per kind over the actors (`from file`,
/// `generated (crease 60°), 645 vertices split, in 12.3 ms`, `geometric`), in the order
/// the actors first show each; the actor counts appear when kinds are mixed.
pub fn normals_summary(scene: &Scene, shading_ms: f64) -> String {
    // (label, actors, split vertices, generated)
    let mut kinds: Vec<(String, usize, usize, bool)> = Vec::new();
    for a in &scene.actors {
        let label = a.normal_source.to_string();
        let (split, generated) = match a.normal_source {
            NormalSource::Generated { split_vertices, .. } => (split_vertices, true),
            _ => (0, false),
        };
        match kinds.iter_mut().find(|k| k.0 == label) {
            Some(k) => {
                k.1 += 1;
                k.2 += split;
            }
            None => kinds.push((label, 1, split, generated)),
        }
    }
    let mixed = kinds.len() > 1;
    let parts: Vec<String> = kinds
        .iter()
        .map(|(label, actors, split, generated)| {
            let mut s = label.clone();
            if mixed {
                s += &format!(" for {} actor{}", thousands(*actors), if *actors == 1 { "" } else { "s" });
            }
            if *generated {
                s += &format!(", {} vertices split", thousands(*split));
            }
            s
        })
        .collect();
    let mut summary = if parts.is_empty() { "none (no actors)".to_string() } else { parts.join("; ") };
    if kinds.iter().any(|k| k.3) {
        summary += &format!(", in {shading_ms:.1} ms");
    }
    summary
}

/// One line on what moves: frames and rate, clips, nodes, skins, dynamic actors.
pub fn animation_summary(scene: &Scene) -> String {
    if !scene.is_animated() {
        return "none (a still scene)".into();
    }
    let a = &scene.animation;
    let t = a.timeline;
    let mut parts = vec![format!(
        "{} frames at {} fps from {} s to {} s",
        thousands(t.frames as usize),
        // Three decimals at most: BART's rates are (N - 1) / duration.
        format!("{:.3}", t.frame_rate).trim_end_matches('0').trim_end_matches('.'),
        t.time_of(0),
        t.time_of(t.frames - 1)
    )];
    let clips = &a.rig.clips;
    if clips.len() > 1 {
        let names: Vec<String> =
            clips.iter().enumerate().map(|(i, c)| c.name.clone().unwrap_or_else(|| format!("#{i}"))).collect();
        parts.push(format!("clips {} (playing {})", names.join(", "), names[a.rig.active_clip.min(names.len() - 1)]));
    } else if let Some(name) = clips.first().and_then(|c| c.name.as_deref()) {
        parts.push(format!("clip {name}"));
    }
    if !a.rig.nodes.is_empty() {
        parts.push(format!("{} nodes", thousands(a.rig.nodes.len())));
    }
    if !a.rig.skins.is_empty() {
        parts.push(match a.rig.skins.len() {
            1 => "1 skin".to_string(),
            n => format!("{n} skins"),
        });
    }
    let dynamic = scene.actors.iter().filter(|x| x.motion == dynray_scene::Motion::Dynamic).count();
    parts.push(format!("{dynamic} of {} actors dynamic", scene.actors.len()));
    parts.join("; ")
}
