//! Host harness for raymip: f64 references, scene loaders, renderer.
