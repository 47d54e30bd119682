// IPOPT peer: written next
