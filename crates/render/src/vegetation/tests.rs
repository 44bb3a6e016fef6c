//! Forest tests: the BVH against brute force.
