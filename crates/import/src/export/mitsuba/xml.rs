//! A small XML tree for Mitsuba 3's scene format: elements with attributes and children,
//! written indented, attribute values escaped.

use glam::{Mat4, Vec3};
use std::fmt::Write;

/// One element: `<name key="value" …>children</name>`, or a comment.
#[derive(Clone, Debug)]
pub struct Element {
    name: String,
    attrs: Vec<(String, String)>,
    children: Vec<Node>,
}

#[derive(Clone, Debug)]
enum Node {
    Element(Element),
    Comment(String),
}

impl Element {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            attrs: Vec::new(),
            children: Vec::new(),
        }
    }

    /// `<name type="kind">`: a plugin.
    pub fn plugin(name: &str, kind: &str) -> Self {
        Self::new(name).attr("type", kind)
    }

    pub fn attr(mut self, key: &str, value: impl ToString) -> Self {
        self.attrs.push((key.to_string(), value.to_string()));
        self
    }

    pub fn child(mut self, child: Element) -> Self {
        self.children.push(Node::Element(child));
        self
    }

    pub fn push(&mut self, child: Element) {
        self.children.push(Node::Element(child));
    }

    /// An XML comment of `text` (made one: [`comment_text`]).
    pub fn comment(&mut self, text: &str) {
        self.children.push(Node::Comment(comment_text(text)));
    }

    /// A named property of a plugin: `<kind name="name" value="value"/>`.
    pub fn property(kind: &str, name: &str, value: impl ToString) -> Self {
        Self::new(kind).attr("name", name).attr("value", value)
    }

    pub fn float(name: &str, value: f32) -> Self {
        Self::property("float", name, value)
    }

    pub fn integer(name: &str, value: impl ToString) -> Self {
        Self::property("integer", name, value)
    }

    pub fn boolean(name: &str, value: bool) -> Self {
        Self::property("boolean", name, value)
    }

    pub fn string(name: &str, value: &str) -> Self {
        Self::property("string", name, value)
    }

    pub fn rgb(name: &str, [r, g, b]: [f32; 3]) -> Self {
        Self::property("rgb", name, format!("{r}, {g}, {b}"))
    }

    pub fn point(name: &str, p: Vec3) -> Self {
        Self::new("point")
            .attr("name", name)
            .attr("x", p.x)
            .attr("y", p.y)
            .attr("z", p.z)
    }

    /// `<transform name="name"><matrix value="…"/></transform>`, the rows of `m`.
    pub fn matrix(name: &str, m: Mat4) -> Self {
        Self::transform(name, (0..4).flat_map(|r| m.row(r).to_array()))
    }

    /// As [`Element::matrix`], of the 3 × 3 `m` (a texture's `to_uv`).
    pub fn matrix3(name: &str, m: glam::Mat3) -> Self {
        Self::transform(name, (0..3).flat_map(|r| m.row(r).to_array()))
    }

    /// `<transform name="name"><matrix value="…"/></transform>` of the numbers row by row.
    fn transform(name: &str, numbers: impl Iterator<Item = f32>) -> Self {
        let value = numbers.map(|x| x.to_string()).collect::<Vec<_>>().join(" ");
        Self::new("transform")
            .attr("name", name)
            .child(Self::new("matrix").attr("value", value))
    }

    /// The element and its children, indented by `depth` levels.
    pub fn write(&self, out: &mut String, depth: usize) {
        let pad = "    ".repeat(depth);
        write!(out, "{pad}<{}", self.name).ok();
        for (k, v) in &self.attrs {
            write!(out, " {k}=\"{}\"", escape(v)).ok();
        }
        if self.children.is_empty() {
            out.push_str("/>\n");
            return;
        }
        out.push_str(">\n");
        for child in &self.children {
            match child {
                Node::Element(e) => e.write(out, depth + 1),
                Node::Comment(c) => writeln!(out, "{pad}    <!-- {c} -->").unwrap_or(()),
            }
        }
        writeln!(out, "{pad}</{}>", self.name).ok();
    }
}

/// `text` as an XML comment may hold it: no `--` anywhere (a run of dashes is spaced out, `---`
/// too) and no `-` at the end.
pub fn comment_text(text: &str) -> String {
    let mut out = text.to_string();
    while out.contains("--") {
        out = out.replace("--", "- -");
    }
    if out.ends_with('-') {
        out.push(' ');
    }
    out
}

/// `text` with XML's special characters as entities.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elements_nest_and_escape_their_attributes() {
        let mut scene = Element::new("scene").attr("version", "3.0.0");
        scene.comment("a --- b-");
        scene.push(
            Element::plugin("bsdf", "diffuse").child(Element::rgb("reflectance", [0.5, 1.0, 0.25])),
        );
        scene.push(Element::string("filename", "a&b\"<c>.ply"));
        let mut out = String::new();
        scene.write(&mut out, 0);
        assert_eq!(
            out,
            "<scene version=\"3.0.0\">\n    <!-- a - - - b-  -->\n    <bsdf type=\"diffuse\">\n        \
             <rgb name=\"reflectance\" value=\"0.5, 1, 0.25\"/>\n    </bsdf>\n    \
             <string name=\"filename\" value=\"a&amp;b&quot;&lt;c&gt;.ply\"/>\n</scene>\n"
        );
    }
}
