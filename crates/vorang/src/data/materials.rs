//! The `Materials` enumeration (thesis B.2 "Materialblock"): byte values with a name and any
//! number of physical constants (`eps`, `sigma`, `rho`, …), used by `byte Materials` data.

use std::fmt;

/// One value of a `key=value` pair. Numbers keep the text they were written with so that a file
/// is written back as it was read.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialValue {
    Number { value: f64, text: String },
    Text(String),
}

impl fmt::Display for MaterialValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MaterialValue::Number { text, .. } => f.write_str(text),
            MaterialValue::Text(s) => f.write_str(s),
        }
    }
}

/// `{ id=0, name="Tumor", eps=1.25, sigma=986 }`.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub id: u8,
    pub name: String,
    /// The other pairs, in file order.
    pub props: Vec<(String, MaterialValue)>,
}

impl Material {
    /// A numeric property such as `sigma`.
    pub fn prop(&self, key: &str) -> Option<f64> {
        self.props.iter().find_map(|(k, v)| match v {
            MaterialValue::Number { value, .. } if k == key => Some(*value),
            _ => None,
        })
    }
}

/// The whole block.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Materials {
    pub list: Vec<Material>,
}

impl Materials {
    pub fn get(&self, id: u8) -> Option<&Material> {
        self.list.iter().find(|m| m.id == id)
    }

    /// The block as written in a header, one material per line.
    pub fn to_header(&self) -> String {
        let mut s = String::from("Materials {\n");
        for (i, m) in self.list.iter().enumerate() {
            s.push_str(&format!("  {{ id={}, name=\"{}\"", m.id, m.name));
            for (k, v) in &m.props {
                match v {
                    MaterialValue::Number { text, .. } => s.push_str(&format!(", {k}={text}")),
                    MaterialValue::Text(t) => s.push_str(&format!(", {k}=\"{t}\"")),
                }
            }
            s.push_str(if i + 1 < self.list.len() {
                " },\n"
            } else {
                " }\n"
            });
        }
        s.push_str("}\n");
        s
    }
}
