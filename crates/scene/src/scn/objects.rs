//! Models and actors (seed 003 A.2): `mesh`, `box`, `sphere`, `object name`,
//! `object { name modifiers }`, and the modifiers (`material`, `transform`) they share.
//!
//! An object is a list of parts (a mesh file with several materials gives several), each
//! with its shape, its accumulated transform and its material. Spheres stay analytic
//! (centre, radius) until the whole file is read, so that `settings { sphere_detail }`
//! applies to every sphere wherever it is written; see `build.rs`.

use super::animate::AnimSpec;
use super::diag::did_you_mean;
use super::diag::FileId;
use super::lexer::Tok;
use super::mesh_file::{load_mesh_file, MeshFile, Parts};
use super::parser::{Def, Parser, Span, R};
use super::textures::shifted;
use crate::shapes::cuboid;
use crate::{Light, LightKind, Material, Motion, Shading, DEFAULT_CREASE_DEG};
use dynray_geom::TriangleMesh;
use glam::{DMat4, Vec3};
use std::collections::HashMap;
use std::rc::Rc;

/// Geometry of a part before its transform.
#[derive(Clone, Debug)]
pub(crate) enum Shape {
    /// Triangles (inline mesh, box, mesh file). Shared between instances.
    Mesh(Rc<TriangleMesh>),
    /// A sphere, tessellated when the scene is built.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius (> 0).
        radius: f32,
    },
}

/// One piece of an object.
#[derive(Clone, Debug)]
pub(crate) struct Part {
    pub shape: Shape,
    /// Object-to-world transform, applied to the shape's points.
    pub transform: DMat4,
    /// `None`: the scene's default material.
    pub material: Option<Rc<Material>>,
}

/// A model: what `define name sphere { … }` names and what an actor places.
#[derive(Clone, Debug, Default)]
pub(crate) struct Object {
    pub parts: Vec<Part>,
    /// Lights that come with the geometry (a mesh file's lamps), in world space: each
    /// placement of the object adds them to the scene.
    pub lights: Vec<Light>,
    /// How the actor placing it is shaded: a mesh's `shading` parameter, else `Auto`
    /// (file normals kept, generated where there are none) for mesh files, boxes and
    /// spheres (whose own normals are kept), and `Flat` for inline meshes without normals.
    pub shading: Shading,
    /// The object's `animate` block, if it has one (docs §5.3).
    pub anim: Option<ObjAnim>,
    /// `motion static|dynamic` as written, with where.
    pub motion: Option<(Motion, FileId, Span)>,
    /// The `elastic { … }` block (a simulated body, docs/physics.md), with where.
    pub elastic: Option<(crate::ElasticParams, FileId, Span)>,
}

/// An object's animation: the keys, and the transforms written after `animate` (they
/// apply after the animated one; those written before are in the parts).
#[derive(Clone, Debug)]
pub(crate) struct ObjAnim {
    pub spec: Rc<AnimSpec>,
    pub after: DMat4,
}

/// Midpoint subdivisions of a box with an `elastic` block: 4 gives 16 × 16 quads a face
/// (3,072 triangles), enough for its bending to show.
pub const ELASTIC_BOX_LEVELS: u32 = 4;

/// Largest crease angle `shading smooth` accepts, in degrees (180 smooths every edge).
pub const MAX_CREASE_DEG: f64 = 180.0;

impl Object {
    fn single(shape: Shape) -> Self {
        Object {
            parts: vec![Part { shape, transform: DMat4::IDENTITY, material: None }],
            lights: Vec::new(),
            shading: Shading::Auto,
            anim: None,
            motion: None,
            elastic: None,
        }
    }

    /// Applies `m` after the transforms already there, to the parts and their lights.
    /// After an `animate`, `m` applies after the animation (parts and lights stay in the
    /// animation's space).
    fn transform(&mut self, m: DMat4) {
        if let Some(a) = &mut self.anim {
            a.after = m * a.after;
            return;
        }
        for p in &mut self.parts {
            p.transform = m * p.transform;
        }
        for l in &mut self.lights {
            *l = transform_light(l, &m);
        }
    }

    /// Starts the object's animation: transforms from here on apply after it. An object
    /// has one animation (a defined one included).
    fn animate(&mut self, spec: Rc<AnimSpec>, p: &Parser) -> R<()> {
        if let Some(first) = &self.anim {
            return Err(p
                .err(spec.span.clone(), "a second `animate` for one object")
                .label("an object has one `animate` block")
                .also(first.spec.file, first.spec.span.clone(), "the first is here"));
        }
        self.anim = Some(ObjAnim { spec, after: DMat4::IDENTITY });
        Ok(())
    }

    /// Sets `motion`; given twice (in a definition and where it is used, say) is an error.
    fn set_motion(&mut self, m: (Motion, Span), p: &Parser) -> R<()> {
        if let Some((_, f, s)) = &self.motion {
            return Err(p.err(m.1, "duplicated parameter `motion`").label("given again here").also(
                *f,
                s.clone(),
                "first given here",
            ));
        }
        self.motion = Some((m.0, p.file, m.1));
        Ok(())
    }

    /// Gives every part `m`, replacing what the parts had. Lights that stood in for a
    /// mesh file's emissive surfaces (an OBJ's `Ke` lamp) lose their surface's emission
    /// with it, so they become ordinary lights, which the path tracer then samples too
    /// (the lamp keeps lighting the scene as it did under Whitted).
    fn set_material(&mut self, m: &Rc<Material>) {
        for p in &mut self.parts {
            p.material = Some(m.clone());
        }
        if m.emission.max_element() <= 0.0 {
            for l in &mut self.lights {
                l.emitter_stand_in = false;
            }
        }
    }

    /// Names the anonymous materials of a defined object after it (diagnostics only).
    pub(crate) fn name_materials(&mut self, name: &str) {
        for p in &mut self.parts {
            if let Some(m) = &mut p.material {
                if m.name.is_empty() {
                    Rc::make_mut(m).name = name.to_string();
                }
            }
        }
    }
}

/// `light` moved by `m`: positions as points, directions by the linear part (then
/// normalised; their length carries no meaning).
fn transform_light(light: &Light, m: &DMat4) -> Light {
    let point = |p: Vec3| m.transform_point3(p.as_dvec3()).as_vec3();
    let dir = |d: Vec3| m.transform_vector3(d.as_dvec3()).as_vec3().normalize_or_zero();
    let kind = match light.kind {
        LightKind::Point { position, falloff } => LightKind::Point { position: point(position), falloff },
        LightKind::Directional { direction } => LightKind::Directional { direction: dir(direction) },
        LightKind::Spot { position, direction, cos_inner, cos_outer, falloff } => {
            LightKind::Spot { position: point(position), direction: dir(direction), cos_inner, cos_outer, falloff }
        }
    };
    Light { kind, ..*light }
}

impl Parser<'_> {
    /// `Objeto`: a primitive, `object name` or `object { name modifiers }`. Returns the
    /// actor name (`Some` for the named forms) and the object.
    pub(crate) fn object(&mut self) -> R<(Option<String>, Object)> {
        let (word, word_span) = self.name("an object")?;
        match word.as_str() {
            "mesh" => Ok((None, self.mesh()?)),
            "box" => Ok((None, self.boxx()?)),
            "sphere" => Ok((None, self.sphere()?)),
            "object" if self.at('{') => {
                self.bump();
                let (name, span) = self.name("the name of a defined object")?;
                let mut obj = self.object_named(&name, span)?;
                self.modifiers_until_close(&mut obj, "object")?;
                Ok((Some(name), obj))
            }
            "object" => {
                let (name, span) = self.name("the name of a defined object, or `{`")?;
                Ok((Some(name.clone()), self.object_named(&name, span)?))
            }
            // Callers dispatch only the four words above; an error rather than a panic
            // keeps a future caller's mistake from crashing on someone's input.
            other => Err(self
                .err(word_span, format!("internal error: `{other}` is not an object"))
                .label("expected `mesh`, `box`, `sphere` or `object`")
                .note("this is a bug in dynray; please report it with this file")),
        }
    }

    fn object_named(&self, name: &str, span: Span) -> R<Object> {
        let rc = self.lookup(name, span, "an object", |d| match d {
            Def::Object(o) => Some(o.clone()),
            _ => None,
        })?;
        Ok((*rc).clone())
    }

    /// `Modificador_De_Objeto*` then `}` (the `{` and name already read).
    fn modifiers_until_close(&mut self, obj: &mut Object, what: &str) -> R<()> {
        let mut material_at: Option<Span> = None;
        loop {
            if self.at('}') {
                self.bump();
                return Ok(());
            }
            if MODIFIERS.iter().any(|m| self.at_word(m)) {
                self.modifier(obj, what, &mut material_at)?;
            } else {
                return Err(self.expected(&format!("`material`, `transform` or `}}` to close `{what}`")).note(
                    "an object's block also takes `animate { … }` and `motion static|dynamic` (docs §5.3, §5.4)",
                ));
            }
        }
    }

    /// One modifier; the keyword is the current token.
    fn modifier(&mut self, obj: &mut Object, what: &str, material_at: &mut Option<Span>) -> R<()> {
        let span = self.span();
        if self.at_word("material") {
            if let Some(first) = material_at.clone() {
                return Err(self
                    .err(span, format!("duplicated parameter `material` in `{what}`"))
                    .label("given again here")
                    .also(self.file, first, "first given here"));
            }
            *material_at = Some(span);
            self.bump();
            let m = self.material()?;
            obj.set_material(&m);
        } else if self.at_word("animate") {
            self.bump();
            let spec = self.animate(span)?;
            obj.animate(Rc::new(spec), self)?;
        } else if self.at_word("motion") {
            self.bump();
            let m = self.motion()?;
            obj.set_motion(m, self)?;
        } else {
            self.bump();
            let m = self.transform()?;
            obj.transform(m);
        }
        Ok(())
    }

    /// `mesh { (file "…" | vertices … [normals …] triangles …) [shading …] modifiers }`.
    fn mesh(&mut self) -> R<Object> {
        let mut file: Option<(Parts, Vec<Light>)> = None;
        let mut vertices: Option<Vec<Vec3>> = None;
        let mut normals: Option<(Vec<Vec3>, Span)> = None;
        let mut triangles: Option<Vec<Tri>> = None;
        let mut shading: Option<Shading> = None;
        let mut inline_key: Option<(String, Span)> = None;
        let mut file_key: Option<Span> = None;
        let (block, mods) = self.primitive_block("mesh", &MESH_KEYS, |p, key, span| {
            if key == "file" {
                file_key = Some(span.clone());
            } else if key != "shading" && inline_key.is_none() {
                inline_key = Some((key.to_string(), span.clone()));
            }
            match key {
                "file" => {
                    let (rel, s) = p.string("a quoted file name")?;
                    let path = p.dir.join(&rel);
                    let MeshFile { mut parts, lights, textures, warnings } = load_mesh_file(&path).map_err(|e| {
                        p.err(s, format!("cannot load mesh file `{rel}`")).label("this file").note(e.to_string())
                    })?;
                    p.st.warnings.extend(warnings);
                    // The file's materials name its textures; renumber into the scene's.
                    let base = p.add_decoded_textures(textures);
                    for m in parts.iter_mut().filter_map(|(_, m)| m.as_mut()) {
                        m.diffuse_texture = m.diffuse_texture.map(|t| shifted(t, base));
                    }
                    file = Some((parts, lights));
                }
                "vertices" => vertices = Some(p.vector_list("vertices", "vertex")?),
                "normals" => {
                    let n = p.vector_list("normals", "normal")?;
                    normals = Some((n, span.start..p.prev_end()));
                }
                "triangles" => triangles = Some(p.triangle_list()?),
                "shading" => shading = Some(p.shading()?),
                other => return Err(p.unhandled(span, other, "mesh")),
            }
            Ok(())
        })?;
        let mut obj = match file {
            Some((parts, lights)) => {
                if let (Some((k, s)), Some(f)) = (inline_key, file_key) {
                    return Err(self
                        .err(s, format!("`{k}` cannot be combined with `file` in one `mesh`"))
                        .label("expected either `file` or inline mesh data")
                        .also(self.file, f, "`file` given here"));
                }
                Object {
                    parts: parts
                        .into_iter()
                        .map(|(m, mat)| Part {
                            shape: Shape::Mesh(Rc::new(m)),
                            transform: DMat4::IDENTITY,
                            material: mat.map(Rc::new),
                        })
                        .collect(),
                    lights,
                    shading: shading.unwrap_or(Shading::Auto),
                    anim: None,
                    motion: None,
                    elastic: None,
                }
            }
            None => {
                let v = self.required(vertices, "vertices", "mesh", &block)?;
                let t = self.required(triangles, "triangles", "mesh", &block)?;
                let mesh = self.inline_mesh(v, normals, t)?;
                // Seed 003: a triangle without normals uses its own; normals that are
                // given are kept (`Auto` keeps them). `shading` overrides either.
                let default = if mesh.normals.is_some() { Shading::Auto } else { Shading::Flat };
                Object { shading: shading.unwrap_or(default), ..Object::single(Shape::Mesh(Rc::new(mesh))) }
            }
        };
        mods.apply(&mut obj);
        Ok(obj)
    }

    /// `shading auto | flat | smooth [crease]` (the key already read); the crease is an
    /// expression in degrees, `0..=180`, and defaults to [`DEFAULT_CREASE_DEG`]. It is
    /// present unless the next token closes the block or is one of the block's keys.
    fn shading(&mut self) -> R<Shading> {
        const WORDS: [&str; 3] = ["auto", "flat", "smooth"];
        let expected = "`auto`, `flat` or `smooth` after `shading`";
        let (word, span) = self.name(expected)?;
        match word.as_str() {
            "auto" => Ok(Shading::Auto),
            "flat" => Ok(Shading::Flat),
            "smooth" => {
                let crease_given = match self.peek() {
                    Tok::Punct('}') | Tok::Eof => false,
                    Tok::Name(n) => !MESH_KEYS.contains(&n.as_str()) && !MODIFIERS.contains(&n.as_str()),
                    _ => true,
                };
                let crease_deg = if crease_given {
                    self.real_f32("crease angle", "it must lie in 0..=180 degrees", |x| {
                        (0.0..=MAX_CREASE_DEG).contains(&x)
                    })?
                } else {
                    DEFAULT_CREASE_DEG
                };
                Ok(Shading::Smooth { crease_deg })
            }
            other => {
                let mut d = self.err(span, format!("unknown shading `{other}`")).label(format!("expected {expected}"));
                if let Some(s) = did_you_mean(other, WORDS) {
                    d = d.note(format!("did you mean `{s}`?"));
                }
                Err(d)
            }
        }
    }

    /// `static | dynamic` after `motion`, with the word's span.
    fn motion(&mut self) -> R<(Motion, Span)> {
        let (word, span) = self.name("`static` or `dynamic` after `motion`")?;
        match word.as_str() {
            "static" => Ok((Motion::Static, span)),
            "dynamic" => Ok((Motion::Dynamic, span)),
            other => {
                let mut d = self.err(span, format!("unknown motion `{other}`")).label("expected `static` or `dynamic`");
                if let Some(s) = did_you_mean(other, ["static", "dynamic"]) {
                    d = d.note(format!("did you mean `{s}`?"));
                }
                Err(d)
            }
        }
    }

    /// `{ n <v> … }`: a count then exactly that many vectors.
    fn vector_list(&mut self, what: &str, one: &str) -> R<Vec<Vec3>> {
        let open = self.expect('{', &format!("to open `{what}`"))?;
        let n = self.int(&format!("the number of {what}"), 1, u32::MAX as i64)? as usize;
        let mut out = Vec::new();
        while out.len() < n {
            if self.at('}') {
                return Err(self
                    .expected(&format!("{} more {one} vector(s)", n - out.len()))
                    .note(format!("`{what}` declares {n} entries but lists {}", out.len())));
            }
            out.push(self.vector(one)?);
        }
        if !self.at('}') {
            let mut d = self.expected(&format!("`}}` to close `{what}` after its {n} entries")).also(
                self.file,
                open,
                "opened here",
            );
            if self.at_word("normals") || self.at_word("triangles") {
                d = d.note(format!("close `{what} {{ … }}` before `normals`/`triangles`: each is its own block"));
            } else {
                d = d.note(format!("`{what}` declares {n} entries; change the count if there are more"));
            }
            return Err(d);
        }
        self.bump();
        Ok(out)
    }

    /// `{ n <a,b,c>[/<na,nb,nc>] … }`.
    fn triangle_list(&mut self) -> R<Vec<Tri>> {
        let open = self.expect('{', "to open `triangles`")?;
        let n = self.int("the number of triangles", 1, u32::MAX as i64)? as usize;
        let mut out = Vec::new();
        while out.len() < n {
            if self.at('}') {
                return Err(self
                    .expected(&format!("{} more triangle(s) `<a, b, c>`", n - out.len()))
                    .note(format!("`triangles` declares {n} entries but lists {}", out.len())));
            }
            let start = self.span().start;
            let v = self.index_triple()?;
            let vspan = start..self.prev_end();
            let nrm = if self.at('/') {
                self.bump();
                let s = self.span().start;
                Some((self.index_triple()?, s..self.prev_end()))
            } else {
                None
            };
            out.push(Tri { v, vspan, n: nrm });
        }
        if !self.at('}') {
            return Err(self.expected(&format!("`}}` to close `triangles` after its {n} entries")).also(
                self.file,
                open,
                "opened here",
            ));
        }
        self.bump();
        Ok(out)
    }

    /// `'<' int ',' int ',' int '>'` (components may be expressions evaluating to integers).
    fn index_triple(&mut self) -> R<[u32; 3]> {
        self.expect('<', "to start a triangle's indices `<a, b, c>`")?;
        let mut t = [0u32; 3];
        for (i, slot) in t.iter_mut().enumerate() {
            *slot = self.int("a 0-based index", 0, u32::MAX as i64 - 1)? as u32;
            if i < 2 {
                self.expect(',', "between indices")?;
            }
        }
        self.expect('>', "to close the indices (three of them)")?;
        Ok(t)
    }

    /// Builds an inline mesh. Triangles with `/<na,nb,nc>` take those normals; vertices
    /// are split where one position is used with different normals. A triangle without
    /// normal indices uses normal `i` for vertex `i` when there are as many normals as
    /// vertices, and its flat geometric normal otherwise.
    fn inline_mesh(&self, v: Vec<Vec3>, normals: Option<(Vec<Vec3>, Span)>, tris: Vec<Tri>) -> R<TriangleMesh> {
        for t in &tris {
            if let Some(&i) = t.v.iter().find(|&&i| i as usize >= v.len()) {
                return Err(self.err(t.vspan.clone(), format!("vertex index {i} out of range")).label(format!(
                    "expected indices below {} (the mesh has {} vertices)",
                    v.len(),
                    v.len()
                )));
            }
            if let Some((n, s)) = &t.n {
                let count = normals.as_ref().map_or(0, |(ns, _)| ns.len());
                if normals.is_none() {
                    return Err(self
                        .err(s.clone(), "normal indices given but the mesh has no `normals` block")
                        .label("expected a `normals { n <v> … }` block before `triangles`"));
                }
                if let Some(&i) = n.iter().find(|&&i| i as usize >= count) {
                    return Err(self
                        .err(s.clone(), format!("normal index {i} out of range"))
                        .label(format!("expected indices below {count} (the mesh has {count} normals)")));
                }
            }
        }
        let any_split = tris.iter().any(|t| t.n.is_some());
        let positions: Vec<[f32; 3]> = v.iter().map(|p| p.to_array()).collect();
        match normals {
            None => Ok(TriangleMesh::new(positions, tris.iter().map(|t| t.v).collect())),
            Some((ns, _)) if !any_split && ns.len() == v.len() => {
                let mut m = TriangleMesh::new(positions, tris.iter().map(|t| t.v).collect());
                m.normals = Some(ns.iter().map(|n| n.normalize_or_zero().to_array()).collect());
                Ok(m)
            }
            Some((ns, _)) => {
                // One output vertex per distinct (position, normal) pair.
                let same = ns.len() == v.len();
                let mut map: HashMap<(u32, u32), u32> = HashMap::new();
                let mut m = TriangleMesh::default();
                let mut out_n = Vec::new();
                for t in &tris {
                    let mut tri = [0u32; 3];
                    for k in 0..3 {
                        let vi = t.v[k];
                        let ni = match t.n {
                            Some((n, _)) => n[k],
                            None if same => vi,
                            None => u32::MAX,
                        };
                        tri[k] = *map.entry((vi, ni)).or_insert_with(|| {
                            m.positions.push(positions[vi as usize]);
                            let n = ns.get(ni as usize).map_or(Vec3::ZERO, |n| n.normalize_or_zero());
                            out_n.push(n.to_array());
                            m.positions.len() as u32 - 1
                        });
                    }
                    m.indices.push(tri);
                }
                m.normals = Some(out_n);
                Ok(m)
            }
        }
    }

    /// `box { center V orientation V scale V modifiers }`.
    fn boxx(&mut self) -> R<Object> {
        let (mut c, mut o, mut s) = (None, None, None);
        let (block, mods) = self.primitive_block("box", &["center", "orientation", "scale"], |p, key, span| {
            match key {
                "center" => c = Some(p.vector("box center")?),
                "orientation" => o = Some(p.vector("box orientation")?),
                "scale" => {
                    let start = p.span().start;
                    let v = p.vector("box scale")?;
                    if v.min_element() <= 0.0 {
                        return Err(p
                            .err(start..p.prev_end(), format!("box scale {v} has an edge length that is not positive"))
                            .label("expected three positive edge lengths"));
                    }
                    s = Some(v);
                }
                other => return Err(p.unhandled(span, other, "box")),
            }
            Ok(())
        })?;
        let c = self.required(c, "center", "box", &block)?;
        let o = self.required(o, "orientation", "box", &block)?;
        let s = self.required(s, "scale", "box", &block)?;
        let mut obj = Object::single(Shape::Mesh(Rc::new(cuboid(c, s, o))));
        mods.apply(&mut obj);
        if obj.elastic.is_some() {
            // A box of 12 triangles could only shear as a whole: subdivided, it bends.
            for part in &mut obj.parts {
                if let Shape::Mesh(m) = &part.shape {
                    part.shape = Shape::Mesh(Rc::new(crate::shapes::subdivide(m, ELASTIC_BOX_LEVELS)));
                }
            }
        }
        Ok(obj)
    }

    /// `sphere { center V radius R modifiers }`.
    fn sphere(&mut self) -> R<Object> {
        let (mut c, mut r) = (None, None);
        let (block, mods) = self.primitive_block("sphere", &["center", "radius"], |p, key, span| {
            match key {
                "center" => c = Some(p.vector("sphere center")?),
                "radius" => r = Some(p.real_f32("sphere radius", "a radius must be positive", |x| x > 0.0)?),
                other => return Err(p.unhandled(span, other, "sphere")),
            }
            Ok(())
        })?;
        let center = self.required(c, "center", "sphere", &block)?;
        let radius = self.required(r, "radius", "sphere", &block)?;
        let mut obj = Object::single(Shape::Sphere { center, radius });
        mods.apply(&mut obj);
        Ok(obj)
    }

    /// A primitive's block: its own keys (handled by `f`) plus `material` and any number
    /// of `transform`s, recorded in order.
    fn primitive_block<F>(&mut self, what: &str, own: &[&str], mut f: F) -> R<(Span, Mods)>
    where
        F: FnMut(&mut Self, &str, Span) -> R<()>,
    {
        let mut allowed: Vec<&str> = own.to_vec();
        allowed.extend(MODIFIERS);
        // Only a primitive can be a simulated body: its phyxels are sampled from its own
        // closed mesh (docs/physics.md).
        allowed.push("elastic");
        let mut mods = Mods::default();
        let block = self.block(what, &allowed, &["transform"], |p, key, span| match key {
            "animate" => {
                mods.0.push(Mod::Animate(Rc::new(p.animate(span)?)));
                Ok(())
            }
            "motion" => {
                let (m, s) = p.motion()?;
                mods.0.push(Mod::Motion(m, p.file, s));
                Ok(())
            }
            "elastic" => {
                let e = p.elastic()?;
                mods.0.push(Mod::Elastic(e, p.file, span.start..p.prev_end()));
                Ok(())
            }
            "material" => {
                mods.0.push(Mod::Material(p.material()?));
                Ok(())
            }
            "transform" => {
                mods.0.push(Mod::Transform(p.transform()?));
                Ok(())
            }
            _ => f(p, key, span),
        })?;
        Ok((block, mods))
    }
}

/// The modifiers every object block takes (docs §5).
const MODIFIERS: [&str; 4] = ["material", "transform", "animate", "motion"];

/// The keys of a `mesh` block besides the modifiers.
const MESH_KEYS: [&str; 5] = ["file", "vertices", "normals", "triangles", "shading"];

/// A parsed triangle of an inline mesh.
struct Tri {
    v: [u32; 3],
    vspan: Span,
    n: Option<([u32; 3], Span)>,
}

/// A modifier as written.
enum Mod {
    Material(Rc<Material>),
    Transform(DMat4),
    /// Within one block `animate` and `motion` cannot repeat ([`Parser::block`] checks).
    Animate(Rc<AnimSpec>),
    Motion(Motion, FileId, Span),
    Elastic(crate::ElasticParams, FileId, Span),
}

/// Modifiers in written order.
#[derive(Default)]
struct Mods(Vec<Mod>);

impl Mods {
    fn apply(self, obj: &mut Object) {
        for m in self.0 {
            match m {
                Mod::Material(m) => obj.set_material(&m),
                Mod::Transform(t) => obj.transform(t),
                Mod::Animate(a) => obj.anim = Some(ObjAnim { spec: a, after: DMat4::IDENTITY }),
                Mod::Motion(m, f, s) => obj.motion = Some((m, f, s)),
                Mod::Elastic(e, f, s) => obj.elastic = Some((e, f, s)),
            }
        }
    }
}
