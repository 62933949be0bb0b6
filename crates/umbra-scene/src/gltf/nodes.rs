//! The node hierarchy (glTF 2.0 §3.5): checked to be a forest — every child index exists,
//! no node has two parents, no node lies on a cycle, a scene lists only root nodes — and then
//! walked parent before child with world transforms.

use super::source::Source;
use crate::error::SceneResult;
use glam::{Mat4, Quat, Vec3};
use gltf::json::{scene::Node, Root};

/// The nodes of the document's scene in walk order, each with its world transform.
pub(crate) fn walk(root: &Root, src: &Source) -> SceneResult<Vec<(usize, Mat4)>> {
    let n = root.nodes.len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for (i, node) in root.nodes.iter().enumerate() {
        for (k, child) in node.children.iter().flatten().enumerate() {
            let c = child.value();
            let at = || format!("nodes[{i}].children[{k}]");
            if c >= n {
                return Err(src.error(at(), format!("node {c} does not exist (the file has {n})")));
            }
            if let Some(p) = parent[c] {
                let why = format!(
                    "node {c} already has parent {p}: a glTF node hierarchy is a set of disjoint trees (§3.5.3)"
                );
                return Err(src.error(at(), why));
            }
            parent[c] = Some(i);
        }
    }
    // With at most one parent each, a node whose ancestors never reach a root lies on (or
    // below) a cycle; checked before walking, so the walk below always ends.
    if let Some(i) = rooted(&parent).iter().position(|&r| !r) {
        return Err(src.error(format!("nodes[{i}]"), "lies on (or below) a cycle of parent and child links"));
    }
    let roots = scene_roots(root, &parent, src)?;
    let mut order = Vec::with_capacity(n);
    let mut stack: Vec<(usize, Mat4)> = roots.iter().rev().map(|&r| (r, Mat4::IDENTITY)).collect();
    while let Some((i, parent_world)) = stack.pop() {
        let world = parent_world * local(&root.nodes[i]);
        order.push((i, world));
        stack.extend(root.nodes[i].children.iter().flatten().rev().map(|c| (c.value(), world)));
    }
    Ok(order)
}

fn scene_roots(root: &Root, parent: &[Option<usize>], src: &Source) -> SceneResult<Vec<usize>> {
    let scene = match root.scene {
        Some(s) => Some((
            s.value(),
            root.scenes.get(s.value()).ok_or_else(|| {
                src.error("scene", format!("scene {} does not exist (the file has {})", s.value(), root.scenes.len()))
            })?,
        )),
        None => root.scenes.first().map(|s| (0, s)),
    };
    let Some((s, scene)) = scene else {
        return Ok((0..parent.len()).filter(|&i| parent[i].is_none()).collect());
    };
    let mut listed = vec![false; parent.len()];
    let mut roots = Vec::with_capacity(scene.nodes.len());
    for (k, node) in scene.nodes.iter().enumerate() {
        let (i, at) = (node.value(), format!("scenes[{s}].nodes[{k}]"));
        match (parent.get(i), listed.get(i)) {
            (None, _) => return Err(src.error(at, format!("node {i} does not exist (the file has {})", parent.len()))),
            (Some(Some(p)), _) => return Err(src.error(at, format!("node {i} is a child of node {p}, not a root"))),
            (_, Some(true)) => return Err(src.error(at, format!("node {i} is listed twice"))),
            _ => {}
        }
        listed[i] = true;
        roots.push(i);
    }
    Ok(roots)
}

/// Whether each node's chain of parents ends at a root (memoised: linear time).
fn rooted(parent: &[Option<usize>]) -> Vec<bool> {
    let mut known: Vec<Option<bool>> = vec![None; parent.len()];
    for start in 0..parent.len() {
        let (mut path, mut i) = (Vec::new(), start);
        let verdict = loop {
            if let Some(v) = known[i] {
                break v;
            }
            if path.len() > parent.len() {
                break false;
            }
            path.push(i);
            match parent[i] {
                None => break true,
                Some(p) => i = p,
            }
        };
        for j in path {
            known[j] = Some(verdict);
        }
    }
    known.into_iter().map(|v| v == Some(true)).collect()
}

/// A node's local transform: `matrix`, or translation × rotation × scale (§3.5.2).
fn local(node: &Node) -> Mat4 {
    if let Some(m) = node.matrix {
        return Mat4::from_cols_array(&m);
    }
    let t = node.translation.map_or(Vec3::ZERO, Vec3::from);
    let r = node.rotation.as_ref().map_or(Quat::IDENTITY, |q| Quat::from_array(q.0));
    let s = node.scale.map_or(Vec3::ONE, Vec3::from);
    Mat4::from_scale_rotation_translation(s, r, t)
}
