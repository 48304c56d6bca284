//! One entry of a scene file (a body or a joint: a JSON object) read
//! field by field, so that every error names the entry by its index and
//! name and names the field ([`SceneFileError::Body`],
//! [`SceneFileError::Joint`]).

use serde_json::{Map, Value};

use super::scene_file::{FieldProblem, SceneFileError};

/// Which list an entry is in.
#[derive(Debug, Clone, Copy)]
pub(super) enum Entry {
    /// `bodies`.
    Body,
    /// `joints`.
    Joint,
}

/// An entry's fields.
pub(super) struct ObjectReader<'a> {
    entry: Entry,
    index: usize,
    /// The entry's `name`, if it is a string.
    pub(super) name: Option<String>,
    pub(super) object: &'a Map<String, Value>,
}

impl<'a> ObjectReader<'a> {
    /// The reader of entry `index` of `entry`'s list, or the error for an
    /// entry that is not an object (field `(body)` or `(joint)`).
    pub(super) fn new(
        entry: Entry,
        index: usize,
        value: &'a Value,
    ) -> Result<Self, SceneFileError> {
        let Some(object) = value.as_object() else {
            let field = match entry {
                Entry::Body => "(body)",
                Entry::Joint => "(joint)",
            };
            let problem = FieldProblem::WrongType("an object");
            return Err(entry_error(entry, index, None, field, problem));
        };
        let name = object.get("name").and_then(Value::as_str).map(String::from);
        Ok(ObjectReader {
            entry,
            index,
            name,
            object,
        })
    }

    /// The error `problem` at `field` of this entry.
    pub(super) fn error(&self, field: &str, problem: FieldProblem) -> SceneFileError {
        entry_error(self.entry, self.index, self.name.clone(), field, problem)
    }

    /// The value of `field`, or a `Missing` error.
    pub(super) fn required(&self, field: &str) -> Result<&'a Value, SceneFileError> {
        self.object
            .get(field)
            .ok_or_else(|| self.error(field, FieldProblem::Missing))
    }

    /// The entry's `name`, required and a string.
    pub(super) fn name(&self) -> Result<String, SceneFileError> {
        match (self.required("name")?, &self.name) {
            (_, Some(name)) => Ok(name.clone()),
            _ => Err(self.error("name", FieldProblem::WrongType("a string"))),
        }
    }
}

fn entry_error(
    entry: Entry,
    index: usize,
    name: Option<String>,
    field: &str,
    problem: FieldProblem,
) -> SceneFileError {
    let field = field.into();
    match entry {
        Entry::Body => SceneFileError::Body {
            index,
            name,
            field,
            problem,
        },
        Entry::Joint => SceneFileError::Joint {
            index,
            name,
            field,
            problem,
        },
    }
}
