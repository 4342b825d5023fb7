//! An MJCF file as owned elements: `<include>`s expanded in place (files
//! relative to the main file's folder, each bounded in size and nesting),
//! every element knowing the file and line it came from, and the `<default>`
//! classes that fill in what an element does not say.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use roxmltree::{Document, Node};

use super::MjcfError;

/// Included files may include others this deep.
const INCLUDE_DEPTH: usize = 8;
/// At most this many files make one model.
const MAX_FILES: usize = 64;

/// One element of the model.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    /// Its tag.
    pub tag: String,
    /// Its own attributes, as written.
    pub attrs: BTreeMap<String, String>,
    /// The elements it holds, includes expanded.
    pub children: Vec<Element>,
    /// Where it is written: `FILE line N`.
    pub at: String,
}

impl Element {
    /// An error about this element.
    pub fn error(&self, reason: impl Into<String>) -> MjcfError {
        MjcfError {
            at: format!("<{}> at {}", self.tag, self.at),
            reason: reason.into(),
        }
    }

    /// The children with tag `tag`.
    pub fn all<'a>(&'a self, tag: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.tag == tag)
    }
}

/// Reads the model's main file and every file it includes.
pub(crate) fn read(path: &Path) -> Result<Element, MjcfError> {
    let dir = path.parent().unwrap_or_else(|| Path::new("")).to_path_buf();
    let mut files = 0;
    let root = read_file(path, &dir, 0, &mut files)?;
    if root.tag != "mujoco" {
        return Err(root.error("the root element of an MJCF model must be <mujoco>"));
    }
    Ok(root)
}

fn read_file(
    path: &Path,
    dir: &Path,
    depth: usize,
    files: &mut usize,
) -> Result<Element, MjcfError> {
    let name = path.display().to_string();
    let fail = |reason: String| MjcfError {
        at: name.clone(),
        reason,
    };
    *files += 1;
    if *files > MAX_FILES {
        return Err(fail(format!("more than {MAX_FILES} files are included")));
    }
    let text =
        crate::files::read_text(path, crate::files::URDF_LIMIT).map_err(|e| fail(e.to_string()))?;
    crate::files::check_xml(&text).map_err(fail)?;
    let doc = Document::parse(&text).map_err(|e| fail(e.to_string()))?;
    let mut el = element(&doc, doc.root_element(), &name);
    expand(&mut el, dir, depth, files)?;
    Ok(el)
}

fn element(doc: &Document, node: Node, file: &str) -> Element {
    Element {
        tag: node.tag_name().name().to_string(),
        attrs: node
            .attributes()
            .map(|a| (a.name().to_string(), a.value().to_string()))
            .collect(),
        children: node
            .children()
            .filter(Node::is_element)
            .map(|c| element(doc, c, file))
            .collect(),
        at: format!("{file} line {}", doc.text_pos_at(node.range().start).row),
    }
}

/// Replaces every `<include file>` under `el` by what the file's `<mujoco>` holds.
fn expand(el: &mut Element, dir: &Path, depth: usize, files: &mut usize) -> Result<(), MjcfError> {
    let mut out = Vec::with_capacity(el.children.len());
    for mut child in std::mem::take(&mut el.children) {
        if child.tag == "include" {
            if depth >= INCLUDE_DEPTH {
                return Err(child.error(format!("includes nested more than {INCLUDE_DEPTH} deep")));
            }
            let file = child
                .attrs
                .get("file")
                .ok_or_else(|| child.error("has no `file`"))?;
            let path: PathBuf = dir.join(file);
            let included = read_file(&path, dir, depth + 1, files)?;
            if included.tag != "mujoco" {
                return Err(included.error("an included file's root element must be <mujoco>"));
            }
            out.extend(included.children);
        } else {
            expand(&mut child, dir, depth, files)?;
            out.push(child);
        }
    }
    el.children = out;
    Ok(())
}

/// The attributes a class sets, by kind of element (`geom`, `joint`, ...).
type Kinds = HashMap<String, BTreeMap<String, String>>;

/// The default classes: for each class, its parent and, for each kind of
/// element, the attributes it sets.
#[derive(Debug, Default)]
pub(crate) struct Defaults {
    classes: HashMap<String, (Option<String>, Kinds)>,
}

/// The actuator shortcuts, which share one default in a class.
pub(crate) const ACTUATORS: [&str; 5] = ["general", "motor", "position", "velocity", "intvelocity"];

impl Defaults {
    /// The classes `<default>` elements of `root` declare (nested classes
    /// inherit; the top one is `main`).
    pub fn of(root: &Element) -> Result<Self, MjcfError> {
        let mut d = Self::default();
        for top in root.all("default") {
            d.add(top, None)?;
        }
        Ok(d)
    }

    fn add(&mut self, el: &Element, parent: Option<&str>) -> Result<(), MjcfError> {
        let name = match (el.attrs.get("class"), parent) {
            (Some(c), _) => c.clone(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => return Err(el.error("a nested <default> must name its class")),
        };
        if self.classes.contains_key(&name) {
            return Err(el.error(format!("class `{name}` is declared twice")));
        }
        let mut kinds = Kinds::new();
        for c in el.children.iter().filter(|c| c.tag != "default") {
            let kind = if ACTUATORS.contains(&c.tag.as_str()) {
                "actuator"
            } else {
                c.tag.as_str()
            };
            kinds
                .entry(kind.into())
                .or_default()
                .extend(c.attrs.clone());
        }
        self.classes
            .insert(name.clone(), (parent.map(str::to_string), kinds));
        for c in el.all("default") {
            self.add(c, Some(&name))?;
        }
        Ok(())
    }

    /// `el`'s attributes with what its class (its own `class`, else
    /// `class`, the enclosing body's `childclass` or `main`) sets for `kind`
    /// filled in beneath them.
    pub fn resolve(
        &self,
        el: &Element,
        kind: &str,
        class: &str,
    ) -> Result<BTreeMap<String, String>, MjcfError> {
        let class = el.attrs.get("class").map_or(class, String::as_str);
        let mut chain = Vec::new();
        let mut at = Some(class.to_string());
        while let Some(c) = at {
            let Some((parent, kinds)) = self.classes.get(&c) else {
                if c == "main" {
                    break;
                }
                return Err(el.error(format!("names class `{c}`, which no <default> declares")));
            };
            chain.push(kinds.get(kind));
            at = parent.clone();
            if chain.len() > self.classes.len() + 1 {
                return Err(el.error("its classes' parents form a cycle"));
            }
        }
        let mut out = BTreeMap::new();
        for kinds in chain.into_iter().rev().flatten() {
            out.extend(kinds.clone());
        }
        out.extend(el.attrs.clone());
        out.remove("class");
        Ok(out)
    }

    /// Whether class `name` is declared (`main` always is).
    pub fn has(&self, name: &str) -> bool {
        name == "main" || self.classes.contains_key(name)
    }
}
