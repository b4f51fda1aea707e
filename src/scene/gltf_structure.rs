//! What a glTF document must be before Drape walks it: its nodes form
//! trees (no node its own ancestor, none with two parents), and every
//! accessor lies inside its buffer view and every view inside its buffer.
//! The glTF crate's own validation checks indices only; without these a
//! 118-byte file loops forever and a count of 2³¹ reads as nothing or
//! allocates gigabytes.

use glam::{DMat4, Mat4};

/// The glTF document (JSON or GLB) in `bytes`, validated by the glTF crate,
/// or why not in a user's words. A POSITION attribute naming an accessor the
/// file lacks is refused first: the crate's validation indexes it unchecked.
pub fn read_gltf(bytes: &[u8]) -> Result<gltf::Gltf, String> {
    let unreadable = |error: gltf::Error| format!("not a readable glTF file ({error})");
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(bytes).map_err(unreadable)?;
    let json = document.into_json();
    let position = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (index, mesh) in json.meshes.iter().enumerate() {
        for primitive in &mesh.primitives {
            if let Some(accessor) = primitive.attributes.get(&position)
                && accessor.value() >= json.accessors.len()
            {
                let count = json.accessors.len();
                return Err(format!("mesh {index}'s POSITION is accessor {}, and there are {count}", accessor.value()));
            }
        }
    }
    let document = gltf::Document::from_json(json).map_err(unreadable)?;
    Ok(gltf::Gltf { document, blob })
}

/// The file's node hierarchy: every node with at most one parent and no
/// cycle; otherwise which node breaks it, in a user's words.
pub fn check_node_trees(document: &gltf::Document) -> Result<(), String> {
    let count = document.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            let (child, index) = (child.index(), node.index());
            if let Some(first) = parent[child].replace(index) {
                let how = if first == index { "twice".to_owned() } else { format!("of nodes {first} and {index}") };
                return Err(format!("node {child} is listed as a child {how}: glTF nodes form trees"));
            }
        }
    }
    // Walking up from each node ends within `count` steps unless it meets a cycle.
    let mut state = vec![Walk::Unseen; count];
    for start in 0..count {
        let mut path = Vec::new();
        let mut at = Some(start);
        while let Some(node) = at {
            match state[node] {
                Walk::Done => break,
                Walk::OnPath => return Err(format!("node {node} is its own ancestor: glTF nodes form trees")),
                Walk::Unseen => {
                    state[node] = Walk::OnPath;
                    path.push(node);
                    at = parent[node];
                }
            }
        }
        path.into_iter().for_each(|node| state[node] = Walk::Done);
    }
    Ok(())
}

#[derive(Clone, Copy, PartialEq)]
enum Walk {
    Unseen,
    OnPath,
    Done,
}

/// Every node of `scene` once, each after its parent, with its transform to
/// the scene. The document's trees must have been checked
/// ([`check_node_trees`]); a root listed twice is still walked once.
pub fn scene_nodes<'a>(document: &'a gltf::Document, scene: &gltf::Scene<'a>) -> Vec<(gltf::Node<'a>, DMat4)> {
    let mut seen = vec![false; document.nodes().len()];
    let mut walked = Vec::new();
    let mut stack: Vec<(gltf::Node, DMat4)> = scene.nodes().map(|n| (n, DMat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            continue;
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        stack.extend(node.children().map(|child| (child, world)));
        walked.push((node, world));
    }
    walked
}

/// Every accessor, sparse parts included, lies inside its buffer view, every
/// view inside its buffer, and every buffer within the bytes read for it
/// (`buffers`, in the document's order); an accessor without a view holds
/// no more elements than the file has bytes (at least 65 536), so nothing
/// read from it outgrows the file. Otherwise which part is wrong.
pub fn check_accessors(document: &gltf::Document, buffers: &[Vec<u8>]) -> Result<(), String> {
    for view in document.views() {
        let buffer = view.buffer();
        let held = buffers.get(buffer.index()).map_or(0, Vec::len).min(buffer.length());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|end| end > held) {
            return Err(format!(
                "buffer view {} ends past its buffer {} ({} bytes)",
                view.index(),
                buffer.index(),
                buffer.length()
            ));
        }
    }
    let file_bytes: usize = buffers.iter().map(Vec::len).sum();
    for accessor in document.accessors() {
        let what = format!("accessor {}", accessor.index());
        let (count, size) = (accessor.count(), accessor.size());
        if count == 0 {
            return Err(format!("{what} has no elements (a count of 0)"));
        }
        match accessor.view() {
            Some(view) => fits(&what, &view, accessor.offset(), count, size)?,
            None if count.saturating_mul(size) > file_bytes.max(1 << 16) => {
                return Err(format!("{what} has {count} elements and no data: more than the file holds"));
            }
            None => {}
        }
        if let Some(sparse) = accessor.sparse() {
            let sparse_count = sparse.count();
            if sparse_count == 0 || sparse_count > count {
                return Err(format!("{what} changes {sparse_count} of its {count} elements"));
            }
            let indices = sparse.indices();
            fits(
                &format!("{what}'s sparse indices"),
                &indices.view(),
                indices.offset(),
                sparse_count,
                indices.index_type().size(),
            )?;
            let values = sparse.values();
            fits(&format!("{what}'s sparse values"), &values.view(), values.offset(), sparse_count, size)?;
        }
    }
    Ok(())
}

/// Every animation channel targets a node the file has, by a property glTF
/// names (translation, rotation, scale or weights): the glTF crate's
/// validation leaves channel targets unchecked, and its readers stop the
/// program on either.
pub fn check_animation_targets(document: &gltf::Document) -> Result<(), String> {
    let json = document.as_json();
    for (index, animation) in json.animations.iter().enumerate() {
        for (channel, target) in animation.channels.iter().map(|c| &c.target).enumerate() {
            let what = format!("animation {index} channel {channel}");
            if target.node.value() >= json.nodes.len() {
                return Err(format!("{what} targets node {}, and there are {}", target.node.value(), json.nodes.len()));
            }
            if !matches!(target.path, gltf::json::validation::Checked::Valid(_)) {
                return Err(format!("{what} animates a property glTF does not name"));
            }
        }
    }
    Ok(())
}

/// Every image names its bytes: a buffer view with a MIME type, or a URI.
/// The glTF crate's validation accepts an image with neither, or a view
/// without a type, and its reader stops the program on them.
pub fn check_images(document: &gltf::Document) -> Result<(), String> {
    for (index, image) in document.as_json().images.iter().enumerate() {
        let named = match (&image.buffer_view, &image.uri) {
            (Some(_), _) => image.mime_type.is_some(),
            (None, uri) => uri.is_some(),
        };
        if !named {
            return Err(format!("image {index} has no URI, or a buffer view without a MIME type"));
        }
    }
    Ok(())
}

/// Every accessor a reader of Drape's reads has the element type and
/// component type the glTF specification gives its use (a joint index is
/// four unsigned integers, a position three floats); the glTF crate's
/// readers assume them, and stop the program on others.
pub fn check_accessor_types(document: &gltf::Document) -> Result<(), String> {
    use gltf::accessor::{DataType::*, Dimensions::*};
    use gltf::animation::Property;
    use gltf::mesh::Semantic;
    let weights_types = [F32, I8, U8, I16, U16];
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let what = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            for (semantic, accessor) in primitive.attributes() {
                let (dimensions, types): (&[_], &[_]) = match semantic {
                    Semantic::Positions | Semantic::Normals => (&[Vec3], &[F32]),
                    Semantic::Tangents => (&[Vec4], &[F32]),
                    Semantic::Colors(_) => (&[Vec3, Vec4], &[F32, U8, U16]),
                    Semantic::TexCoords(_) => (&[Vec2], &[F32, U8, U16]),
                    Semantic::Joints(_) => (&[Vec4], &[U8, U16]),
                    Semantic::Weights(_) => (&[Vec4], &[F32, U8, U16]),
                    _ => continue,
                };
                is_of(&format!("{what}'s {}", semantic.to_string().as_str()), &accessor, dimensions, types)?;
            }
            if let Some(indices) = primitive.indices() {
                is_of(&format!("{what}'s indices"), &indices, &[Scalar], &[U8, U16, U32])?;
            }
            for target in primitive.morph_targets() {
                for accessor in [target.positions(), target.normals(), target.tangents()].into_iter().flatten() {
                    is_of(&format!("{what}'s morph target"), &accessor, &[Vec3], &[F32])?;
                }
            }
        }
    }
    for skin in document.skins() {
        if let Some(matrices) = skin.inverse_bind_matrices() {
            is_of(&format!("skin {}'s inverse bind matrices", skin.index()), &matrices, &[Mat4], &[F32])?;
        }
    }
    for animation in document.animations() {
        for channel in animation.channels() {
            let what = format!("animation {} channel {}", animation.index(), channel.index());
            let sampler = channel.sampler();
            is_of(&format!("{what}'s times"), &sampler.input(), &[Scalar], &[F32])?;
            let (dimensions, types): (&[_], &[_]) = match channel.target().property() {
                Property::Translation | Property::Scale => (&[Vec3], &[F32]),
                Property::Rotation => (&[Vec4], &weights_types),
                Property::MorphTargetWeights => (&[Scalar], &weights_types),
            };
            is_of(&format!("{what}'s values"), &sampler.output(), dimensions, types)?;
        }
    }
    Ok(())
}

/// `accessor` has one of `dimensions` and one of `types`.
fn is_of(
    what: &str,
    accessor: &gltf::Accessor,
    dimensions: &[gltf::accessor::Dimensions],
    types: &[gltf::accessor::DataType],
) -> Result<(), String> {
    let (dimension, data_type) = (accessor.dimensions(), accessor.data_type());
    if dimensions.contains(&dimension) && types.contains(&data_type) {
        return Ok(());
    }
    Err(format!("{what} (accessor {}) is {dimension:?} of {data_type:?}, which it cannot be", accessor.index()))
}

/// `count` elements of `size` bytes from `offset` in `view`, at the view's
/// stride, end inside the view.
fn fits(what: &str, view: &gltf::buffer::View, offset: usize, count: usize, size: usize) -> Result<(), String> {
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(format!("{what}: its stride of {stride} bytes is shorter than an element ({size} bytes)"));
    }
    let end = stride.checked_mul(count - 1).and_then(|s| s.checked_add(offset)).and_then(|s| s.checked_add(size));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{what}: {count} elements of {size} bytes do not fit its buffer view {} ({} bytes)",
            view.index(),
            view.length()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn document(json: &str) -> gltf::Document {
        gltf::Gltf::from_slice(json.as_bytes()).unwrap().document
    }

    fn nodes(children: &[&[usize]]) -> gltf::Document {
        let nodes: Vec<String> = children.iter().map(|c| format!("{{\"children\": {c:?}}}")).collect();
        document(&format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{}]}}"#,
            nodes.join(",")
        ))
    }

    #[test]
    fn cycles_and_shared_children_are_refused() {
        assert_eq!(check_node_trees(&nodes(&[&[1], &[2], &[]])), Ok(()));
        assert_eq!(check_node_trees(&nodes(&[&[1, 2], &[], &[]])), Ok(()));
        assert_eq!(
            check_node_trees(&nodes(&[&[1], &[0]])),
            Err("node 0 is its own ancestor: glTF nodes form trees".to_owned())
        );
        assert_eq!(
            check_node_trees(&nodes(&[&[0]])),
            Err("node 0 is its own ancestor: glTF nodes form trees".to_owned())
        );
        assert_eq!(
            check_node_trees(&nodes(&[&[1, 1], &[]])),
            Err("node 1 is listed as a child twice: glTF nodes form trees".to_owned())
        );
        assert_eq!(
            check_node_trees(&nodes(&[&[2], &[2], &[]])),
            Err("node 2 is listed as a child of nodes 0 and 1: glTF nodes form trees".to_owned())
        );
    }

    #[test]
    fn a_tree_is_walked_once_parents_first() {
        let doc = nodes(&[&[1, 2], &[3], &[], &[]]);
        let scene = doc.scenes().next().unwrap();
        let order: Vec<usize> = scene_nodes(&doc, &scene).iter().map(|(n, _)| n.index()).collect();
        assert_eq!(order, vec![0, 2, 1, 3]);
    }

    fn with_accessor(accessor: &str, view: &str) -> gltf::Document {
        document(&format!(
            r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": 36}}],
                "bufferViews": [{view}],
                "accessors": [{accessor}]}}"#
        ))
    }

    #[test]
    fn accessors_must_fit_their_views_and_buffers() {
        let buffers = vec![vec![0u8; 36]];
        let ok = with_accessor(
            r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}"#,
            r#"{"buffer": 0, "byteLength": 36}"#,
        );
        assert_eq!(check_accessors(&ok, &buffers), Ok(()));
        let huge = with_accessor(
            r#"{"bufferView": 0, "componentType": 5126, "count": 2147483648, "type": "VEC3"}"#,
            r#"{"buffer": 0, "byteLength": 36}"#,
        );
        assert!(check_accessors(&huge, &buffers).unwrap_err().contains("do not fit its buffer view 0 (36 bytes)"));
        let long_view = with_accessor(
            r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}"#,
            r#"{"buffer": 0, "byteOffset": 4, "byteLength": 36}"#,
        );
        assert!(check_accessors(&long_view, &buffers).unwrap_err().contains("ends past its buffer 0"));
        let short_stride = with_accessor(
            r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}"#,
            r#"{"buffer": 0, "byteLength": 36, "byteStride": 4}"#,
        );
        assert!(check_accessors(&short_stride, &buffers).unwrap_err().contains("shorter than an element"));
        // Sparse with no base view: every element but the one changed is zero.
        let no_data = with_accessor(
            r#"{"componentType": 5126, "count": 2147483648, "type": "VEC3", "sparse": {"count": 1,
                "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0, "byteOffset": 4}}}"#,
            r#"{"buffer": 0, "byteLength": 36}"#,
        );
        assert!(check_accessors(&no_data, &buffers).unwrap_err().contains("no data"));
        // The buffer read is shorter than the views need.
        assert!(check_accessors(&ok, &[vec![0u8; 20]]).unwrap_err().contains("ends past its buffer 0"));
    }

    #[test]
    fn animation_targets_must_name_a_node_and_a_property() {
        let animated = |node: usize, path: &str| {
            document(&format!(
                r#"{{"asset": {{"version": "2.0"}}, "nodes": [{{}}],
                    "buffers": [{{"byteLength": 8}}], "bufferViews": [{{"buffer": 0, "byteLength": 8}}],
                    "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR"}}],
                    "animations": [{{"samplers": [{{"input": 0, "output": 0}}],
                                     "channels": [{{"sampler": 0, "target": {{"node": {node}, "path": "{path}"}}}}]}}]}}"#
            ))
        };
        assert_eq!(check_animation_targets(&animated(0, "weights")), Ok(()));
        assert_eq!(
            check_animation_targets(&animated(3, "weights")),
            Err("animation 0 channel 0 targets node 3, and there are 1".to_owned())
        );
        assert_eq!(
            check_animation_targets(&animated(0, "translatiox")),
            Err("animation 0 channel 0 animates a property glTF does not name".to_owned())
        );
        // Weights are scalars; a translation is three floats, not one.
        assert_eq!(check_accessor_types(&animated(0, "weights")), Ok(()));
        assert!(check_accessor_types(&animated(0, "translation")).unwrap_err().contains("is Scalar of F32"));
    }

    #[test]
    fn an_image_names_its_bytes() {
        let with_image = |image: &str| {
            document(&format!(
                r#"{{"asset": {{"version": "2.0"}}, "buffers": [{{"byteLength": 4}}],
                    "bufferViews": [{{"buffer": 0, "byteLength": 4}}], "images": [{image}]}}"#
            ))
        };
        assert_eq!(check_images(&with_image(r#"{"uri": "a.png"}"#)), Ok(()));
        assert_eq!(check_images(&with_image(r#"{"bufferView": 0, "mimeType": "image/png"}"#)), Ok(()));
        let message = "image 0 has no URI, or a buffer view without a MIME type".to_owned();
        assert_eq!(check_images(&with_image(r#"{"bufferView": 0}"#)), Err(message.clone()));
        assert_eq!(check_images(&with_image("{}")), Err(message));
    }
}
