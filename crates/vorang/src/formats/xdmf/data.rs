//! XDMF DataItems: values written in the XML (`Format="XML"`) or a dataset of an HDF5 file
//! (`Format="HDF"`, text `file.h5:/path`, the file relative to the XDMF file's folder). The
//! HDF5 files a step names are opened once per step and memory-mapped.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::tree::Node;
use crate::error::ParseError;
use crate::formats::ArrayValues;
use crate::formats::hdf::H5;

/// The values of a DataItem and its dimensions.
pub struct Data {
    pub dims: Vec<usize>,
    pub values: ArrayValues,
}

impl Data {
    /// Values per row: the product of the dimensions after the first (1 for 1-D data).
    pub fn row(&self) -> usize {
        self.dims.iter().skip(1).product::<usize>().max(1)
    }
}

/// Reads DataItems of one XDMF file, keeping the HDF5 files it opened.
pub struct Items<'a> {
    /// The XDMF file as given, for messages.
    pub source: &'a str,
    folder: PathBuf,
    open: HashMap<String, H5>,
}

impl<'a> Items<'a> {
    pub fn new(source: &'a str) -> Items<'a> {
        Items {
            source,
            folder: Path::new(source)
                .parent()
                .unwrap_or(Path::new(""))
                .to_path_buf(),
            open: HashMap::new(),
        }
    }

    pub fn error(&self, line: usize, message: impl Into<String>) -> ParseError {
        ParseError::new(self.source, line, message)
    }

    /// The values of `item` (a `DataItem`), checked against its `Dimensions`.
    pub fn read(&mut self, item: &Node) -> Result<Data, ParseError> {
        if item.name != "DataItem" {
            return Err(self.error(
                item.line,
                format!("expected a DataItem, found <{}>", item.name),
            ));
        }
        let dims = self.dims(item)?;
        if let Some(kind) = item.attr("ItemType").filter(|k| *k != "Uniform") {
            return Err(self.error(
                item.line,
                format!("DataItem ItemType=\"{kind}\": VoRANG reads Uniform data items"),
            ));
        }
        let values = match item.attr("Format").unwrap_or("XML") {
            "XML" => self.xml_values(item)?,
            "HDF" => self.hdf_values(item)?,
            other => {
                return Err(self.error(
                    item.line,
                    format!("DataItem Format=\"{other}\": VoRANG reads XML and HDF data"),
                ));
            }
        };
        let expected: usize = dims.iter().product();
        if values.len() != expected {
            return Err(self.error(
                item.line,
                format!(
                    "DataItem Dimensions=\"{}\" means {expected} values, found {}",
                    item.attr("Dimensions").unwrap_or(""),
                    values.len()
                ),
            ));
        }
        Ok(Data { dims, values })
    }

    fn dims(&self, item: &Node) -> Result<Vec<usize>, ParseError> {
        let text = item
            .attr("Dimensions")
            .ok_or_else(|| self.error(item.line, "DataItem without Dimensions"))?;
        let dims: Option<Vec<usize>> = text.split_whitespace().map(|d| d.parse().ok()).collect();
        match dims {
            Some(d)
                if !d.is_empty()
                    && d.iter()
                        .try_fold(1usize, |a, &b| a.checked_mul(b))
                        .is_some() =>
            {
                Ok(d)
            }
            _ => Err(self.error(
                item.line,
                format!("DataItem Dimensions=\"{text}\": expected whole numbers"),
            )),
        }
    }

    /// Numbers in the XML text, of the item's NumberType and Precision (XDMF's default:
    /// 4-byte floats).
    fn xml_values(&self, item: &Node) -> Result<ArrayValues, ParseError> {
        let kind = item
            .attr("NumberType")
            .or_else(|| item.attr("DataType"))
            .unwrap_or("Float");
        let precision = item.attr("Precision").unwrap_or("4");
        let words = item.text.split_whitespace();
        let bad = |w: &str| {
            self.error(
                item.line,
                format!("DataItem: \"{w}\" is not a {kind} number"),
            )
        };
        match kind {
            "Float" => {
                if precision == "8" {
                    let v: Result<Vec<f64>, _> = words
                        .map(|w| w.parse::<f64>().map_err(|_| bad(w)))
                        .collect();
                    Ok(ArrayValues::F64(v?))
                } else {
                    let v: Result<Vec<f32>, _> = words
                        .map(|w| w.parse::<f32>().map_err(|_| bad(w)))
                        .collect();
                    Ok(ArrayValues::F32(v?))
                }
            }
            "Int" | "UInt" | "Char" | "UChar" => {
                let v: Result<Vec<i64>, _> = words
                    .map(|w| w.parse::<i64>().map_err(|_| bad(w)))
                    .collect();
                Ok(ArrayValues::Int(v?))
            }
            other => Err(self.error(
                item.line,
                format!(
                    "DataItem NumberType=\"{other}\": expected Float, Int, UInt, Char or UChar"
                ),
            )),
        }
    }

    /// `file.h5:/path/in/file`: the dataset, its file relative to the XDMF file.
    fn hdf_values(&mut self, item: &Node) -> Result<ArrayValues, ParseError> {
        let text = item.text.trim();
        let Some((file, dataset)) = text.rsplit_once(':') else {
            return Err(self.error(
                item.line,
                format!("HDF DataItem \"{text}\": expected FILE:/path/to/dataset"),
            ));
        };
        let line = item.line;
        let source = self.source;
        let relocate = |e: ParseError| ParseError::new(source, line, format!("{e}"));
        if !self.open.contains_key(file) {
            let path = self.folder.join(file);
            if !path.is_file() {
                return Err(self.error(line, format!("{}: no such HDF5 file", path.display())));
            }
            let h5 = H5::open(&path, &path.display().to_string()).map_err(relocate)?;
            self.open.insert(file.to_string(), h5);
        }
        let h5 = &self.open[file];
        h5.read(dataset).map_err(relocate)
    }
}
