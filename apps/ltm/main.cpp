// main.cpp: thin entry point (all logic lives in run_cli, which tests call directly).
#include "cli.h"

int main(int argc, char **argv) {
    return ltm::cli::run_cli(std::vector<std::string>(argv + 1, argv + argc));
}
