//! The recursive-descent parser: token cursor, the generic `{ key value … }` block reader
//! (unknown and duplicated parameters are errors), top-level statements, `define` and
//! `include`. Like the seed's `SceneReader`, it evaluates as it parses: expressions become
//! values and definitions become entries of [`State`] immediately.

use super::animate::AnimSpec;
use super::diag::{did_you_mean, Diag, FileId, Sources};
use super::lexer::{tokenize, Tok, Token};
use super::objects::Object;
use super::textures::SceneTexture;
use super::value::Value;
use super::{MAX_EXPR_DEPTH, MAX_INCLUDE_DEPTH};
use crate::{Camera, Environment, Light, Material, Settings, Warning};
use glam::DMat4;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// `Result` of the parser.
pub(crate) type R<T> = Result<T, Diag>;

/// A byte range in the current file.
pub(crate) type Span = Range<usize>;

/// Words that start statements or definitions, or build colours; they cannot be defined.
pub(crate) const KEYWORDS: &[&str] = &[
    "mesh",
    "box",
    "sphere",
    "object",
    "light",
    "camera",
    "environment",
    "settings",
    "physics",
    "adf",
    "material",
    "transform",
    "define",
    "include",
    "rgb",
];

/// What a `define`d name stands for.
#[derive(Clone)]
pub(crate) enum Def {
    /// A real, vector or colour.
    Value(Value),
    /// A model (placed only by `object name`).
    Object(Rc<Object>),
    /// A light (added only by `light name`), with its animation.
    Light(Light, Option<Rc<AnimSpec>>),
    /// A camera (used only by `camera name`), with its animation.
    Camera(Camera, Option<Rc<AnimSpec>>),
    /// A material.
    Material(Rc<Material>),
    /// An affine transform (points are mapped by this matrix).
    Transform(DMat4),
}

impl Def {
    /// "an object", "a light", … for errors.
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            Def::Value(v) => match v {
                Value::Real(_) => "a real",
                Value::Vector(_) => "a vector",
                Value::Color(_) => "a colour",
            },
            Def::Object(_) => "an object",
            Def::Light(..) => "a light",
            Def::Camera(..) => "a camera",
            Def::Material(_) => "a material",
            Def::Transform(_) => "a transform",
        }
    }
}

/// A definition and where it was made.
pub(crate) struct Binding {
    pub def: Def,
    pub file: FileId,
    pub span: Span,
}

/// An actor placed by a statement.
pub(crate) struct ActorEntry {
    /// `Some(name)` for `object name`.
    pub name: Option<String>,
    /// Its parts.
    pub object: Object,
    /// The statement, for errors found when the geometry is finally built.
    pub file: FileId,
    pub span: Span,
}

/// Everything read so far, shared by the main file and its includes.
#[derive(Default)]
pub(crate) struct State {
    pub sources: Sources,
    pub defs: HashMap<String, Binding>,
    pub actors: Vec<ActorEntry>,
    /// The `adf` statements, in order.
    pub fields: Vec<super::field::FieldEntry>,
    pub lights: Vec<Light>,
    /// The camera and where it was set (a second `camera` statement is an error).
    pub camera: Option<(Camera, FileId, Span)>,
    pub environment: Option<(Environment, FileId, Span)>,
    pub settings: Option<(Settings, FileId, Span)>,
    /// The `physics { … }` block and where it was given (once per scene).
    pub physics: Option<(crate::PhysicsSettings, FileId, Span)>,
    /// `settings { sphere_detail n }`: longitude segments of tessellated spheres.
    pub sphere_detail: Option<u32>,
    /// `settings { frames n }` (docs §9; default 1).
    pub frames: Option<u32>,
    /// `settings { frame_rate r }` (default 24).
    pub frame_rate: Option<f32>,
    /// `(light, animation)`: light `light` of `lights` is animated.
    pub light_anims: Vec<(usize, Rc<AnimSpec>)>,
    /// The camera's animation.
    pub camera_anim: Option<Rc<AnimSpec>>,
    /// Canonical paths of the files being read, outermost first (include cycle check).
    pub include_stack: Vec<PathBuf>,
    /// Warnings of the mesh files read so far, in reading order.
    pub warnings: Vec<Warning>,
    /// Textures materials name by index (`.scn` `texture` files and mesh files' own).
    pub textures: Vec<SceneTexture>,
    /// Index in `textures` of each `.scn` texture file named so far.
    pub texture_files: HashMap<PathBuf, u32>,
}

/// Parser of one file.
pub(crate) struct Parser<'s> {
    pub st: &'s mut State,
    pub file: FileId,
    toks: Vec<Token>,
    pos: usize,
    /// Directory of the file: includes and mesh files are relative to it.
    pub dir: PathBuf,
    /// Current expression nesting, bounded by [`MAX_EXPR_DEPTH`].
    pub depth: usize,
}

impl<'s> Parser<'s> {
    /// Tokenizes file `file` of `st.sources`.
    pub(crate) fn new(st: &'s mut State, file: FileId, dir: PathBuf) -> R<Self> {
        let toks = tokenize(file, st.sources.text(file))?;
        Ok(Self { st, file, toks, pos: 0, dir, depth: 0 })
    }

    // ---- token cursor -------------------------------------------------------------

    /// The current token.
    pub(crate) fn peek(&self) -> &Tok {
        &self.toks[self.pos.min(self.toks.len() - 1)].tok
    }

    /// The span of the current token.
    pub(crate) fn span(&self) -> Span {
        self.toks[self.pos.min(self.toks.len() - 1)].span.clone()
    }

    /// The end of the previous token (for spans that cover several tokens).
    pub(crate) fn prev_end(&self) -> usize {
        if self.pos == 0 {
            0
        } else {
            self.toks[(self.pos - 1).min(self.toks.len() - 1)].span.end
        }
    }

    /// Consumes and returns the current token (never moves past end of file).
    pub(crate) fn bump(&mut self) -> Token {
        let t = self.toks[self.pos.min(self.toks.len() - 1)].clone();
        if self.pos < self.toks.len() - 1 {
            self.pos += 1;
        }
        t
    }

    /// An error at the current token: "expected {what}, found {token}".
    pub(crate) fn expected(&self, what: &str) -> Diag {
        Diag::new(self.file, self.span(), format!("expected {what}, found {}", self.peek().describe()))
            .label(format!("expected {what}"))
    }

    /// An error at `span` of this file.
    pub(crate) fn err(&self, span: Span, message: impl Into<String>) -> Diag {
        Diag::new(self.file, span, message)
    }

    /// Whether the current token is punctuation `c`.
    pub(crate) fn at(&self, c: char) -> bool {
        *self.peek() == Tok::Punct(c)
    }

    /// Whether the current token is the name `w`.
    pub(crate) fn at_word(&self, w: &str) -> bool {
        matches!(self.peek(), Tok::Name(n) if n == w)
    }

    /// Consumes punctuation `c` or fails saying `context` needed it.
    pub(crate) fn expect(&mut self, c: char, context: &str) -> R<Span> {
        if self.at(c) {
            Ok(self.bump().span)
        } else {
            Err(self.expected(&format!("`{c}` {context}")))
        }
    }

    /// Consumes a name.
    pub(crate) fn name(&mut self, what: &str) -> R<(String, Span)> {
        match self.peek().clone() {
            Tok::Name(n) => Ok((n, self.bump().span)),
            _ => Err(self.expected(what)),
        }
    }

    /// Consumes a string literal.
    pub(crate) fn string(&mut self, what: &str) -> R<(String, Span)> {
        match self.peek().clone() {
            Tok::Str(s) => Ok((s, self.bump().span)),
            _ => Err(self.expected(what)),
        }
    }

    // ---- blocks -------------------------------------------------------------------

    /// Reads `{ key … key … }`. For each key, `f` parses what follows it. A key not in
    /// `allowed` is an error naming it and listing the allowed ones; a key given twice is
    /// an error unless it is in `repeatable`. Returns the span of the whole block.
    pub(crate) fn block<F>(&mut self, what: &str, allowed: &[&str], repeatable: &[&str], mut f: F) -> R<Span>
    where
        F: FnMut(&mut Self, &str, Span) -> R<()>,
    {
        let open = self.expect('{', &format!("to open `{what}`"))?;
        let mut seen: Vec<(String, Span)> = Vec::new();
        loop {
            if self.at('}') {
                let close = self.bump().span;
                return Ok(open.start..close.end);
            }
            let list = allowed.join(", ");
            let (key, span) = match self.peek().clone() {
                Tok::Name(n) => (n, self.span()),
                Tok::Eof => {
                    return Err(self.expected(&format!("`}}` to close `{what}`")).also(
                        self.file,
                        open.clone(),
                        "block opened here",
                    ))
                }
                _ => return Err(self.expected(&format!("a parameter of `{what}` ({list}) or `}}`"))),
            };
            if !allowed.contains(&key.as_str()) {
                let mut d = self
                    .err(span, format!("unknown parameter `{key}` in `{what}`"))
                    .label(format!("expected one of: {list}"));
                if let Some(s) = did_you_mean(&key, allowed.iter().copied()) {
                    d = d.note(format!("did you mean `{s}`?"));
                }
                return Err(d);
            }
            if !repeatable.contains(&key.as_str()) {
                if let Some((_, first)) = seen.iter().find(|(k, _)| *k == key) {
                    return Err(self
                        .err(span, format!("duplicated parameter `{key}` in `{what}`"))
                        .label("given again here")
                        .also(self.file, first.clone(), "first given here"));
                }
            }
            seen.push((key.clone(), span.clone()));
            self.bump();
            f(self, &key, span)?;
        }
    }

    /// The error for a key that [`Parser::block`] accepted (it is in the block's `allowed`
    /// list) but the block's reader has no arm for. Every reader names each of its keys,
    /// so this is a bug in dynray; it is reported at the key rather than panicking, and
    /// rather than reading the value as some other key, which a catch-all arm once did.
    pub(crate) fn unhandled(&self, span: Span, key: &str, what: &str) -> Diag {
        self.err(span, format!("internal error: parameter `{key}` of `{what}` is accepted but not read"))
            .label("dynray's reader for this block has no case for it")
            .note("this is a bug in dynray; please report it with this file")
    }

    /// A `None` required parameter becomes an error at the block.
    pub(crate) fn required<T>(&self, v: Option<T>, key: &str, what: &str, block: &Span) -> R<T> {
        v.ok_or_else(|| {
            self.err(block.clone(), format!("missing parameter `{key}` in `{what}`"))
                .label(format!("this `{what}` needs `{key}`"))
        })
    }

    // ---- statements ---------------------------------------------------------------

    /// Reads statements until end of file.
    pub(crate) fn file(&mut self) -> R<()> {
        while *self.peek() != Tok::Eof {
            self.statement()?;
        }
        Ok(())
    }

    fn statement(&mut self) -> R<()> {
        let start = self.span();
        let word = match self.peek() {
            Tok::Name(n) => n.clone(),
            _ => return Err(self.statement_expected()),
        };
        match word.as_str() {
            "mesh" | "box" | "sphere" | "object" => {
                let (name, object) = self.object()?;
                let span = start.start..self.prev_end();
                self.st.actors.push(ActorEntry { name, object, file: self.file, span });
            }
            "light" => {
                let (light, anim) = self.light()?;
                if let Some(a) = anim {
                    self.st.light_anims.push((self.st.lights.len(), a));
                }
                self.st.lights.push(light);
            }
            "camera" => {
                let (cam, anim) = self.camera()?;
                let span = start.start..self.prev_end();
                self.once("camera", span.clone(), |st| &mut st.camera)?;
                self.st.camera = Some((cam, self.file, span));
                self.st.camera_anim = anim;
            }
            "environment" => {
                self.bump();
                let env = self.environment()?;
                let span = start.start..self.prev_end();
                self.once("environment", span.clone(), |st| &mut st.environment)?;
                self.st.environment = Some((env, self.file, span));
            }
            "settings" => {
                self.bump();
                let s = self.settings()?;
                let span = start.start..self.prev_end();
                self.once("settings", span.clone(), |st| &mut st.settings)?;
                self.st.settings = Some((s, self.file, span));
            }
            "physics" => {
                self.bump();
                let s = self.physics()?;
                let span = start.start..self.prev_end();
                self.once("physics", span.clone(), |st| &mut st.physics)?;
                self.st.physics = Some((s, self.file, span));
            }
            "adf" => {
                let field = self.distance_field()?;
                self.st.fields.push(field);
            }
            "define" => self.define()?,
            "include" => self.include()?,
            "material" | "transform" => {
                return Err(self
                    .err(start, format!("a `{word}` on its own places nothing"))
                    .label("expected a statement")
                    .note(format!(
                        "name it with `define my_{word} {word} {{ … }}`, or write it inside an object's block"
                    )))
            }
            _ => return Err(self.statement_expected()),
        }
        Ok(())
    }

    fn statement_expected(&self) -> Diag {
        let d = self.expected(
            "a statement (mesh, box, sphere, object, adf, light, camera, environment, settings, physics, define, include)",
        );
        match self.peek() {
            Tok::Name(n) => match did_you_mean(n, KEYWORDS.iter().copied()) {
                Some(s) => d.note(format!("did you mean `{s}`?")),
                None => d,
            },
            _ => d,
        }
    }

    /// Fails if the statement kind behind `slot` (camera, environment, settings) was
    /// already given: a second one would silently replace the first.
    fn once<T>(
        &mut self,
        what: &str,
        span: Span,
        slot: impl Fn(&mut State) -> &mut Option<(T, FileId, Span)>,
    ) -> R<()> {
        let first = slot(self.st).as_ref().map(|(_, f, s)| (*f, s.clone()));
        if let Some((f, s)) = first {
            return Err(self
                .err(span, format!("a second `{what}` statement"))
                .label(format!("a scene has one `{what}`"))
                .also(f, s, "the first is here"));
        }
        Ok(())
    }

    fn define(&mut self) -> R<()> {
        self.bump();
        let (name, span) = self.name("a name to define")?;
        if KEYWORDS.contains(&name.as_str()) {
            return Err(self
                .err(span, format!("`{name}` is a keyword and cannot be defined"))
                .label("expected a name that is not a keyword"));
        }
        if self.at('=') {
            self.bump();
        }
        let def = match self.peek() {
            Tok::Name(w) if matches!(w.as_str(), "mesh" | "box" | "sphere" | "object") => {
                let (_, mut object) = self.object()?;
                object.name_materials(&name);
                Def::Object(Rc::new(object))
            }
            Tok::Name(w) if w == "light" => {
                let (l, a) = self.light()?;
                Def::Light(l, a)
            }
            Tok::Name(w) if w == "camera" => {
                let (c, a) = self.camera()?;
                Def::Camera(c, a)
            }
            Tok::Name(w) if w == "material" => {
                self.bump();
                let mut m = (*self.material()?).clone();
                m.name = name.clone();
                Def::Material(Rc::new(m))
            }
            Tok::Name(w) if w == "transform" => {
                self.bump();
                Def::Transform(self.transform()?)
            }
            // `define b = bola`: another name for any kind of definition.
            Tok::Name(w) if self.aliasable(w) => {
                let (other, _) = self.name("a name")?;
                self.st.defs[&other].def.clone()
            }
            _ => Def::Value(self.expr()?.0),
        };
        // A later definition of the same name replaces the earlier one from here on (as
        // POV-Ray's #declare): statements already read keep what they used.
        self.st.defs.insert(name, Binding { def, file: self.file, span });
        Ok(())
    }

    /// Whether `define x = w …` copies the definition `w` (an object, light, camera,
    /// material or transform) rather than evaluating an expression.
    fn aliasable(&self, w: &str) -> bool {
        matches!(self.st.defs.get(w), Some(b) if !matches!(b.def, Def::Value(_)))
    }

    /// Looks up `name` (at `span`) and checks it is `kind` with `pick`.
    pub(crate) fn lookup<T>(&self, name: &str, span: Span, kind: &str, pick: impl Fn(&Def) -> Option<T>) -> R<T> {
        match self.st.defs.get(name) {
            None => {
                let mut d =
                    self.err(span, format!("unknown name `{name}`")).label(format!("expected the name of {kind}"));
                if let Some(s) = did_you_mean(name, self.st.defs.keys().map(String::as_str)) {
                    d = d.note(format!("did you mean `{s}`?"));
                }
                Err(d)
            }
            Some(b) => pick(&b.def).ok_or_else(|| {
                self.err(span, format!("`{name}` is {}, not {kind}", b.def.kind()))
                    .label(format!("expected {kind}"))
                    .also(b.file, b.span.clone(), "defined here")
            }),
        }
    }

    fn include(&mut self) -> R<()> {
        self.bump();
        let (rel, span) = self.string("a quoted file name after `include`")?;
        let path = self.dir.join(&rel);
        let fail = |p: &Self, msg: String| p.err(span.clone(), msg).label("included here");
        if self.st.include_stack.len() > MAX_INCLUDE_DEPTH {
            return Err(fail(self, format!("includes nested more than {MAX_INCLUDE_DEPTH} deep"))
                .note("an include chain this deep is almost certainly a mistake"));
        }
        let canon = path.canonicalize().map_err(|e| fail(self, format!("cannot open `{}`: {e}", path.display())))?;
        if let Some(k) = self.st.include_stack.iter().position(|p| *p == canon) {
            let chain: Vec<String> =
                self.st.include_stack[k..].iter().chain([&canon]).map(|p| p.display().to_string()).collect();
            return Err(fail(self, format!("include cycle: `{rel}` is already being read"))
                .note(format!("cycle: {}", chain.join(" -> "))));
        }
        let text = dynray_geom::file::read_to_string(&canon)
            .map_err(|e| fail(self, format!("cannot read `{}`: {e}", path.display())))?;
        let file = self.st.sources.add(display_name(&path), canon.clone(), super::without_bom(text));
        let dir = canon.parent().map(Path::to_path_buf).unwrap_or_default();
        self.st.include_stack.push(canon);
        let result = Parser::new(self.st, file, dir).and_then(|mut p| p.file());
        self.st.include_stack.pop();
        let from = self.st.sources.place(self.file, span.start);
        result.map_err(|d| d.note(format!("in a file included from {from}")))
    }

    /// One expression that must span the whole file.
    pub(crate) fn expr_to_end(&mut self) -> R<Value> {
        let (v, _) = self.expr()?;
        if *self.peek() != Tok::Eof {
            return Err(self.expected("an operator or the end of the expression"));
        }
        Ok(v)
    }

    /// Enters one level of expression nesting, failing past [`MAX_EXPR_DEPTH`].
    pub(crate) fn enter(&mut self) -> R<()> {
        self.depth += 1;
        if self.depth > MAX_EXPR_DEPTH {
            return Err(self
                .err(self.span(), format!("expression nested more than {MAX_EXPR_DEPTH} levels deep"))
                .label("too deep here")
                .note("split the expression with `define`"));
        }
        Ok(())
    }

    /// Leaves one level of expression nesting.
    pub(crate) fn leave(&mut self) {
        self.depth -= 1;
    }
}

/// How a path is shown in diagnostics: as written, relative where it was relative.
pub(crate) fn display_name(path: &Path) -> String {
    path.display().to_string()
}
