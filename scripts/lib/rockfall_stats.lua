-- SPDX-License-Identifier: MIT
-- rockfall_stats: the name scripts have always required; the module is rockfall/stats/.
return require("rockfall.stats")
