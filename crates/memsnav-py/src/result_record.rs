//! Results of a fixed shape as frozen Python classes: every field a
//! read-only attribute with its docstring, `to_dict()` for JSON writers
//! and comparisons, and a one-line repr. One macro makes them all, so
//! they behave alike.

/// Declares a result class: `Name as "PythonName" { fields } repr(s) expr`,
/// each field with its doc comment (unit included), the repr an expression
/// of `s` (the record) giving the line inside the parentheses.
macro_rules! result_record {
    (
        $(#[$meta:meta])*
        $rust:ident as $py:literal {
            $( $(#[$field_meta:meta])* $field:ident : $ty:ty ),+ $(,)?
        }
        repr($s:ident) $repr:expr
    ) => {
        $(#[$meta])*
        #[pyo3::pyclass(module = "memsnav._memsnav", name = $py, frozen, get_all)]
        pub struct $rust {
            $( $(#[$field_meta])* pub $field: $ty ),+
        }

        #[pyo3::pymethods]
        impl $rust {
            /// The fields as a dict, by attribute name (records inside stay
            /// records; arrays stay arrays).
            fn to_dict<'py>(
                &self,
                py: pyo3::Python<'py>,
            ) -> pyo3::PyResult<pyo3::Bound<'py, pyo3::types::PyDict>> {
                let d = pyo3::types::PyDict::new(py);
                $( d.set_item(stringify!($field), &self.$field)?; )+
                Ok(d)
            }

            fn __repr__(&self) -> String {
                let $s = self;
                format!("{}({})", $py, $repr)
            }
        }
    };
}

pub(crate) use result_record;
