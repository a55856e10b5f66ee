// command_model.cpp: the tensor model only where the network runs.
#include "command_model.h"

#include "delegate.h"

namespace ltm::cli {

ModelConfig &CommandModel::cfg() {
#if LTM_WITH_TORCH
    if (tensor) return tensor->model->cfg;
#endif
    return prior.cfg;
}

CommandModel open_command_model(PriorModel prior, bool network_needed, const std::string &why_needed) {
    CommandModel m;
    m.prior = std::move(prior);
    m.network = network_needed || !m.prior.torch_free();
    if (!m.network) return m;   // the prior alone renders it exactly (NeuralRenderer tests)
#if LTM_WITH_TORCH
    m.tensor = load_model(m.prior.path);
#else
    // Before the scene loads: ltm-torch runs the command line (delegate.h).
    throw NeedsLibtorch(m.prior.path + (m.prior.torch_free() ? ": " + why_needed + ", and so libtorch"
                                                         : std::string(": the network of these weights is active, and running it needs libtorch")));
#endif
    return m;
}

}  // namespace ltm::cli
