//! Why ROS parameter files could not be loaded.

/// A parameter file that cannot be read, parsed or used; every variant names the file.
///
/// Happens when a file is missing, is not YAML, or gives a value of the wrong type or out of
/// range; fix the file (the message names the key as roslaunch would place it).
/// Unknown and unused keys are not errors: they come back as warnings.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ParamError {
    /// The file could not be read.
    #[error("{file}: {source}")]
    Read {
        /// The file as given.
        file: String,
        /// What went wrong.
        source: std::io::Error,
    },
    /// The text is not YAML, or not a map of parameters.
    #[error("{file}: {message}")]
    Yaml {
        /// The file as given.
        file: String,
        /// The parser's message.
        message: String,
    },
    /// A parameter has the wrong type or is out of range.
    #[error("{file}: {key}: {message}")]
    Value {
        /// The file that set the parameter (the last one, when several did).
        file: String,
        /// The parameter's full name, `/`-separated, as roslaunch places it.
        key: String,
        /// What is wrong, with the value found.
        message: String,
    },
    /// A `FILE[@NAMESPACE]` argument that does not parse.
    #[error("`{arg}`: {message}")]
    Argument {
        /// The argument as given.
        arg: String,
        /// What is wrong.
        message: String,
    },
}
