//! Ray tracing of height fields: grid tracing, maximum mipmaps, cameras.
